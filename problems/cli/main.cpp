// The `tailor` command line: argument parsing and exit codes only; the work is in
// problems/commands.hpp.
//
// Exit codes: 0 success; 1 the solve, a derivative check, the gradient check or the
// optimization failed (or an output could not be written); 2 bad input (scene or mesh errors)
// or bad usage.
#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "forward/mesh/mesh.hpp"
#include "problems/builtin_scenes.hpp"
#include "problems/commands.hpp"
#include "problems/damping_design/damping_design_scene.hpp"
#include "problems/dynamic_scene.hpp"
#include "problems/inverse_commands.hpp"
#include "problems/modes_command.hpp"
#include "problems/rods/rod_scene.hpp"
#include "problems/material_fit/material_fit_scene.hpp"
#include "tailor_version.hpp"

namespace {

constexpr int kSuccess = 0;
constexpr int kFailure = 1;
constexpr int kBadInput = 2;

const char* const kUsage =
    "usage: tailor <verb> [arguments]\n"
    "\n"
    "verbs:\n"
    "  simulate [scene.json] [--out DIR]\n"
    "      Solve a static scene for equilibrium; write DIR/report.json and DIR/result.vtu\n"
    "      (DIR defaults to out/<scene name>). Without a scene, run a built-in cantilever.\n"
    "  check [scene.json] [--seed N]\n"
    "      Check the derivatives of every energy term of the scene's model against finite\n"
    "      differences at a randomly perturbed state (seed N, default 1).\n"
    "  gradcheck scene.json [--out DIR] [--seed N] [--hessian]\n"
    "      Taylor test of the gradient (and with --hessian of the Hessian-vector products)\n"
    "      of the scene's inverse problem at its initial design; write DIR/gradcheck.json.\n"
    "      For a dynamic scene (no inverse section): the time-dependent adjoint of its\n"
    "      dynamics.objective.\n"
    "  run scene.json [--out DIR] [--quiet]\n"
    "      Optimize the design of the scene's inverse problem; print one line per iteration\n"
    "      (none with --quiet); write DIR/report.json and DIR/result.vtu at the best design.\n"
    "      A scene with a \"damping_design\" section runs the example-based damping study.\n"
    "  modes scene.json [--out DIR] [--count N]\n"
    "      Modal analysis at rest: the N lowest vibration modes (default 10), rigid-body modes\n"
    "      set apart; write DIR/report.json (frequencies in Hz) and DIR/modes.vtu.\n"
    "\n"
    "options:\n"
    "  -h, --help     show this message\n"
    "  --version      print the version\n"
    "\n"
    "exit codes: 0 success, 1 solve, check or optimization failed (or did not converge),\n"
    "2 bad input or usage.\n"
    "The scene format is described in README.md, section \"Scenes, verbs and reports\".\n";

int usage_error(const std::string& what) {
  std::cerr << "tailor: " << what << "\n\n" << kUsage;
  return kBadInput;
}

struct Arguments {
  std::optional<std::string> scene;
  std::optional<std::string> out_dir;
  std::optional<unsigned> seed;
  bool hessian = false;
  bool quiet = false;
  bool help = false;
  int count = 10;  // modes
};

// Parses the arguments after the verb; returns an error message on bad usage.
std::optional<std::string> parse_arguments(const std::string& verb, const std::vector<std::string>& args,
                                           Arguments& out) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    const bool has_value = i + 1 < args.size();
    if (a == "-h" || a == "--help") {
      out.help = true;
    } else if (a == "--out" && verb != "check") {
      if (!has_value) return "--out needs a folder";
      out.out_dir = args[++i];
    } else if (a == "--hessian" && verb == "gradcheck") {
      out.hessian = true;
    } else if (a == "--quiet" && verb == "run") {
      out.quiet = true;
    } else if (a == "--seed" && (verb == "check" || verb == "gradcheck")) {
      if (!has_value) return "--seed needs a number";
      const std::string& value = args[++i];
      char* end = nullptr;
      const unsigned long seed = std::strtoul(value.c_str(), &end, 10);
      if (value.empty() || *end != '\0') return "--seed needs a non-negative integer, got '" + value + "'";
      out.seed = static_cast<unsigned>(seed);
    } else if (a == "--count" && verb == "modes") {
      if (!has_value) return "--count needs a number";
      const std::string& value = args[++i];
      char* end = nullptr;
      const long count = std::strtol(value.c_str(), &end, 10);
      if (value.empty() || *end != '\0' || count < 1 || count > 100000)
        return "--count needs a positive integer, got '" + value + "'";
      out.count = static_cast<int>(count);
    } else if (!a.empty() && a[0] == '-') {
      return "unknown option '" + a + "' for '" + verb + "'";
    } else if (out.scene) {
      return "more than one scene given ('" + *out.scene + "', '" + a + "')";
    } else {
      out.scene = a;
    }
  }
  return std::nullopt;
}

bool is_inverse_verb(const std::string& verb) { return verb == "gradcheck" || verb == "run"; }

tailor::Scene load_scene(const Arguments& args) {
  if (args.scene) return tailor::read_scene(*args.scene);
  std::cout
      << "no scene given: using the built-in cantilever (10 x 1 x 1 Neo-Hookean beam, clamped at x = 0, "
         "end traction downwards)\n";
  return tailor::builtin_cantilever();
}

int run_verb(const std::string& verb, const Arguments& args) {
  if (verb == "run" && args.scene && tailor::is_material_fit_scene(*args.scene)) {
    const auto fit = tailor::run_material_fit_scene(*args.scene, args.out_dir.value_or(""), &std::cout,
                                                    args.quiet ? nullptr : &std::cout);
    return fit.result.converged() ? kSuccess : kFailure;
  }
  if (verb == "run" && args.scene && tailor::is_damping_design_scene(*args.scene))
    return tailor::run_damping_design_scene(*args.scene, args.out_dir.value_or("out/damping_design"), std::cout)
               ? kSuccess
               : kFailure;
  if (verb == "simulate" && args.scene && tailor::is_rod_scene(*args.scene))
    return tailor::simulate_rod_scene_file(*args.scene, args.out_dir.value_or("out/rods"), std::cout) ? kSuccess
                                                                                                      : kFailure;
  const tailor::Scene scene = load_scene(args);
  const std::string out_dir = args.out_dir ? *args.out_dir : "out/" + scene.name;
  if (verb == "simulate" && scene.dynamics)
    return tailor::simulate_dynamic_scene(scene, out_dir, &std::cout).completed ? kSuccess : kFailure;
  if (verb == "simulate") {
    const tailor::SimulateRun run = tailor::simulate_scene(scene, out_dir, &std::cout);
    return run.solution.converged ? kSuccess : kFailure;
  }
  if (verb == "gradcheck") {
    const tailor::GradcheckRun run =
        scene.dynamics && !scene.inverse
            ? tailor::gradcheck_dynamic_scene(scene, out_dir, args.seed.value_or(1), &std::cout)
            : tailor::gradcheck_scene(scene, out_dir, {args.seed, args.hessian}, &std::cout);
    if (!run.passed()) {
      const tailor::TaylorTestResult& failed = run.gradient.passed() ? *run.hessian : run.gradient;
      std::cout << (run.gradient.passed() ? "Hessian" : "gradient") << " check "
                << tailor::to_string(failed.status) << ": " << failed.message << "\n";
    }
    return run.passed() ? kSuccess : kFailure;
  }
  if (verb == "modes") return (tailor::modes_scene(scene, args.count, out_dir, &std::cout), kSuccess);
  if (verb == "run") {
    const tailor::InverseRun run =
        tailor::run_inverse_scene(scene, out_dir, &std::cout, args.quiet ? nullptr : &std::cout);
    return run.result.converged() ? kSuccess : kFailure;
  }
  return tailor::check_scene(scene, args.seed.value_or(1), std::cout) ? kSuccess : kFailure;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> all(argv + 1, argv + argc);
  if (all.empty()) return usage_error("no verb given");
  const std::string& verb = all[0];
  if (verb == "-h" || verb == "--help") {
    std::cout << kUsage;
    return kSuccess;
  }
  if (verb == "--version") {
    std::cout << "tailor " << tailor::version_string << "\n";
    return kSuccess;
  }
  if (verb != "simulate" && verb != "check" && verb != "modes" && !is_inverse_verb(verb))
    return usage_error("unknown verb '" + verb + "'");

  Arguments args;
  if (const auto error = parse_arguments(verb, {all.begin() + 1, all.end()}, args))
    return usage_error(*error);
  if (args.help) {
    std::cout << kUsage;
    return kSuccess;
  }
  if (verb == "modes" && !args.scene) return usage_error("'modes' needs a scene file");
  if (is_inverse_verb(verb) && !args.scene)
    return usage_error("'" + verb + "' needs a scene file with an \"inverse\" section");
  try {
    return run_verb(verb, args);
  } catch (const tailor::SceneError& e) {
    std::cerr << "tailor: error: " << e.what() << "\n";
    return kBadInput;
  } catch (const tailor::MeshError& e) {
    std::cerr << "tailor: error: " << e.what() << "\n";
    return kBadInput;
  } catch (const std::exception& e) {
    std::cerr << "tailor: error: " << e.what() << "\n";
    return kFailure;
  }
}
