// The `tailor` command line: argument parsing and exit codes only; the work is in
// problems/commands.hpp.
//
// Exit codes: 0 success; 1 the solve, a derivative check, the gradient check or the
// optimization failed (or an output could not be written); 2 bad input (scene or mesh errors)
// or bad usage.
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "forward/mesh/mesh.hpp"
#include "forward/solve/threads.hpp"
#include "problems/builtin_scenes.hpp"
#include "problems/commands.hpp"
#include "problems/contact/rigid_scene.hpp"
#include "problems/damping_design/damping_design_scene.hpp"
#include "problems/dynamic_commands.hpp"
#include "problems/homogenization/homogenize_command.hpp"
#include "problems/inverse_commands.hpp"
#include "problems/modes_command.hpp"
#include "problems/rods/rod_scene.hpp"
#include "problems/material_fit/material_fit_scene.hpp"
#include "problems/metamaterial/metamaterial_scene.hpp"
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
    "  run scene.json [--out DIR] [--quiet] [--checkpoint-every K] [--resume DIR]\n"
    "      Optimize the design of the scene's inverse problem; print one line per iteration\n"
    "      (none with --quiet); write DIR/report.json and DIR/result.vtu at the best design,\n"
    "      and DIR/checkpoint.json every K iterations (default: the scene's\n"
    "      optimizer.checkpoint_every, 10; 0 = none). --resume DIR continues from DIR's\n"
    "      checkpoint (and writes into DIR unless --out is given).\n"
    "      A scene with a \"damping_design\" section runs the example-based damping study.\n"
    "  modes scene.json [--out DIR] [--count N]\n"
    "      Modal analysis at rest: the N lowest vibration modes (default 10), rigid-body modes\n"
    "      set apart; write DIR/report.json (frequencies in Hz) and DIR/modes.vtu.\n"
    "  homogenize cell.json [--out DIR]\n"
    "      Effective elasticity of a periodic cell (\"type\": \"periodic_cell\"); write\n"
    "      DIR/report.json, PNG plots of E(d) and nu(d) and the cell fields per unit macro strain\n"
    "      (.vtu). \"run\" on a periodic-cell scene with a \"design\" section designs the cell.\n"
    "\n"
    "options:\n"
    "  --threads N    threads for tailor's loops and for BLAS (default: one per core)\n"
    "  --factorization-threads 1|0\n"
    "                 CHOLMOD's own OpenMP loops: 1 serialized (default, fastest measured),\n"
    "                 0 as CHOLMOD was built; overrides the scene's solver.threads\n"
    "  -h, --help     show this message\n"
    "  --version      print the version\n"
    "\n"
    "exit codes: 0 success, 1 solve, check or optimization failed (or did not converge),\n"
    "2 bad input or usage.\n"
    "The scene format is described in docs/scenes.md.\n";

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
  std::optional<std::string> resume;  // run: the checkpoint folder to continue from
  std::optional<int> checkpoint_every;
  std::optional<int> threads, factorization_threads;
};

// A whole non-negative integer within [0, max], or nullopt.
std::optional<int> parse_count(const std::string& value, long max) {
  char* end = nullptr;
  const long n = std::strtol(value.c_str(), &end, 10);
  if (value.empty() || *end != '\0' || n < 0 || n > max) return std::nullopt;
  return static_cast<int>(n);
}

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
    } else if (a == "--resume" && verb == "run") {
      if (!has_value) return "--resume needs the folder of a checkpoint";
      out.resume = args[++i];
    } else if (a == "--checkpoint-every" && verb == "run") {
      if (!has_value) return "--checkpoint-every needs a number";
      const std::string& value = args[++i];
      out.checkpoint_every = parse_count(value, 1000000000);
      if (!out.checkpoint_every)
        return "--checkpoint-every needs a non-negative integer, got '" + value + "'";
    } else if (a == "--count" && verb == "modes") {
      if (!has_value) return "--count needs a number";
      const std::string& value = args[++i];
      const std::optional<int> count = parse_count(value, 100000);
      if (!count || *count < 1) return "--count needs a positive integer, got '" + value + "'";
      out.count = *count;
    } else if (a == "--threads") {
      if (!has_value) return "--threads needs a number";
      const std::string& value = args[++i];
      out.threads = parse_count(value, 4096);
      if (!out.threads || *out.threads < 1) return "--threads needs a positive integer, got '" + value + "'";
    } else if (a == "--factorization-threads") {
      if (!has_value) return "--factorization-threads needs 1 or 0";
      const std::string& value = args[++i];
      out.factorization_threads = parse_count(value, 1);
      if (!out.factorization_threads) return "--factorization-threads needs 1 or 0, got '" + value + "'";
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

// The scene's solver.threads (when given), then the command line's flags on top.
void apply_threads(const Arguments& args, const std::optional<tailor::ThreadSettings>& scene_threads) {
  tailor::ThreadSettings threads = scene_threads.value_or(tailor::thread_settings());
  if (args.threads) threads.assembly = threads.blas = *args.threads;
  if (args.factorization_threads) threads.factorization = *args.factorization_threads;
  tailor::set_thread_settings(threads);
}

int run_verb(const std::string& verb, const Arguments& args) {
  apply_threads(args, std::nullopt);
  const bool checkpoint_flags = args.resume || args.checkpoint_every;
  if (verb == "run" && checkpoint_flags && args.scene &&
      (tailor::is_material_fit_scene(*args.scene) || tailor::is_damping_design_scene(*args.scene) ||
       tailor::is_metamaterial_scene(*args.scene)))
    return usage_error("--resume and --checkpoint-every need a scene with an \"inverse\" section");
  if (verb == "run" && args.scene && tailor::is_material_fit_scene(*args.scene)) {
    const auto fit = tailor::run_material_fit_scene(*args.scene, args.out_dir.value_or(""), &std::cout,
                                                    args.quiet ? nullptr : &std::cout);
    return fit.result.converged() ? kSuccess : kFailure;
  }
  if (verb == "run" && args.scene && tailor::is_damping_design_scene(*args.scene))
    return tailor::run_damping_design_scene(*args.scene, args.out_dir.value_or("out/damping_design"), std::cout)
               ? kSuccess
               : kFailure;
  if ((verb == "simulate" || verb == "gradcheck") && args.scene && tailor::is_rigid_scene(*args.scene)) {
    const tailor::RigidSceneSpec spec = tailor::read_rigid_scene(*args.scene);
    const std::string out_dir = args.out_dir.value_or("out/" + spec.name);
    const unsigned seed = args.seed.value_or(1);
    const bool ok = verb == "gradcheck"
                        ? tailor::gradcheck_rigid_scene(spec, out_dir, seed, &std::cout).passed()
                        : tailor::simulate_rigid_scene(spec, out_dir, &std::cout).completed();
    return ok ? kSuccess : kFailure;
  }
  if (verb == "homogenize") {
    const tailor::CellScene cell = tailor::read_cell_scene(*args.scene);
    return (tailor::homogenize_scene(cell, args.out_dir.value_or("out/" + cell.name), &std::cout), kSuccess);
  }
  if (verb == "run" && args.scene && tailor::is_metamaterial_scene(*args.scene)) {
    const auto design = tailor::run_metamaterial_scene(*args.scene, args.out_dir.value_or("out/metamaterial"),
                                                       &std::cout, args.quiet ? nullptr : &std::cout);
    return design.result.converged() ? kSuccess : kFailure;
  }
  if (verb == "simulate" && args.scene && tailor::is_rod_scene(*args.scene))
    return tailor::simulate_rod_scene_file(*args.scene, args.out_dir.value_or("out/rods"), std::cout) ? kSuccess
                                                                                                      : kFailure;
  const tailor::Scene scene = load_scene(args);
  apply_threads(args, scene.solver.threads);
  // `run --resume DIR` writes into DIR (the checkpoint's folder) unless --out says otherwise.
  std::string out_dir = args.out_dir ? *args.out_dir : "out/" + scene.name;
  if (verb == "run" && args.resume && !args.out_dir) {
    const std::filesystem::path resume(*args.resume);
    out_dir = !std::filesystem::is_regular_file(resume) ? resume.string()
              : resume.has_parent_path()                ? resume.parent_path().string()
                                                        : ".";
  }
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
    const tailor::InverseRun run = tailor::run_inverse_scene(
        scene, out_dir, &std::cout, args.quiet ? nullptr : &std::cout, {args.checkpoint_every, args.resume});
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
  if (verb != "simulate" && verb != "check" && verb != "modes" && verb != "homogenize" &&
      !is_inverse_verb(verb))
    return usage_error("unknown verb '" + verb + "'");

  Arguments args;
  if (const auto error = parse_arguments(verb, {all.begin() + 1, all.end()}, args))
    return usage_error(*error);
  if (args.help) {
    std::cout << kUsage;
    return kSuccess;
  }
  if ((verb == "modes" || verb == "homogenize") && !args.scene)
    return usage_error("'" + verb + "' needs a scene file");
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
