// tailor's own verbs and scene kinds (problems/scene_kinds.hpp): the one place to add either.
// A new kind is one entry in builtin_scene_kinds() -- how it is recognised from the scene's
// top-level JSON and the verbs it supports, each with a handler -- placed before the kinds that
// would also match its files (the first match wins; the last, "static", matches everything).
// A new flag of a verb is a field in VerbArguments and one line in the verb's `options`.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <limits>
#include <ostream>

#include "problems/cli/flag_checks.hpp"
#include "problems/contact/rigid_scene.hpp"
#include "problems/contact/torus_scene.hpp"
#include "problems/damping_design/damping_design_scene.hpp"
#include "problems/fem/builtin_scenes.hpp"
#include "problems/fem/physics_warnings.hpp"
#include "problems/fem/commands.hpp"
#include "problems/fem/dynamic_commands.hpp"
#include "problems/fem/inverse_commands.hpp"
#include "problems/fem/modes_command.hpp"
#include "problems/fem/reduced_design.hpp"
#include "problems/homogenization/homogenize_command.hpp"
#include "problems/interlocking/interlocking_scene.hpp"
#include "problems/interlocking/macro_scene.hpp"
#include "problems/material_fit/material_fit_scene.hpp"
#include "problems/meshless/meshless_commands.hpp"
#include "problems/metamaterial/metamaterial_scene.hpp"
#include "problems/rods/rod_inverse.hpp"
#include "problems/rods/rod_scene.hpp"
#include "problems/rig/rig_inverse.hpp"
#include "problems/rig/rig_scene.hpp"
#include "problems/scene_kinds.hpp"
#include "problems/scene_node.hpp"

namespace tailor {
namespace {

int exit_code(bool ok) { return ok ? kExitSuccess : kExitFailure; }

// ---- recognising a scene from its top-level JSON

bool has_section(const nlohmann::json& document, const char* key) {
  return document.is_object() && document.contains(key);
}

bool has_type(const nlohmann::json& document, const char* type) {
  return has_section(document, "type") && document["type"] == type;
}

// ---- verbs: their flags

void add_out(CLI::App& command, VerbArguments& args) {
  command.add_option("--out", args.out_dir, "output folder (default: out/<scene name>)")->type_name("DIR");
}

void add_seed(CLI::App& command, VerbArguments& args, const char* what) {
  command.add_option("--seed", args.seed, what)
      ->type_name("N")
      ->check(cli::integer_in(0, std::numeric_limits<unsigned>::max()));
}

// ---- the static and dynamic scenes of docs/scenes.md

// The scene (the built-in cantilever without a file), with its solver.threads applied under the
// command line's thread flags.
Scene load_scene(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  Scene scene;
  if (!file.given()) {
    out << "no scene given: using the built-in cantilever (10 x 1 x 1 Neo-Hookean beam, clamped at x = 0, "
           "end traction downwards)\n";
    scene = builtin_cantilever();
  } else {
    scene = parse_scene(file.node(), file.directory());
    scene.name = file.name();
  }
  for (const std::string& warning : locking_warnings(scene)) out << "warning: " << warning << "\n";
  apply_thread_flags(args, scene.solver.threads);
  return scene;
}


int simulate_static(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  const Scene scene = load_scene(file, args, out);
  return exit_code(simulate_scene(scene, output_folder(file, args), &out).solution.converged);
}

int simulate_dynamic(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  const Scene scene = load_scene(file, args, out);
  return exit_code(simulate_dynamic_scene(scene, output_folder(file, args), &out).completed);
}

int check_model(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  return exit_code(check_scene(load_scene(file, args, out), args.seed.value_or(1), &out));
}

int report_gradcheck(const GradcheckRun& run, std::ostream& out) {
  if (!run.passed()) {
    const TaylorTestResult& failed = run.gradient.passed() ? *run.hessian : run.gradient;
    out << (run.gradient.passed() ? "Hessian" : "gradient") << " check " << to_string(failed.status) << ": "
        << failed.message << "\n";
  }
  return exit_code(run.passed());
}

// --hessian on a kind whose design functional has no Hessian-vector products: bad input (exit 2),
// before any solve.
void refuse_hessian_flag(const SceneFile& file, const VerbArguments& args, const std::string& kind) {
  if (args.hessian)
    throw SceneError(file.source + ": --hessian: " + kind +
                     " have no Hessian-vector products; run gradcheck without --hessian to check the gradient");
}

int gradcheck_inverse(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  const Scene scene = load_scene(file, args, out);
  if (scene.inverse && scene.inverse->design.reduction) {
    // The reduced design loop's functional (problems/fem/reduced_design.hpp) at w = 0.
    if (args.hessian)
      throw SceneError(scene.source + ": " + scene.inverse->design.reduction->key +
                       ": the reduced design loop has no Hessian-vector products (--hessian)");
    ReducedDesign design = build_reduced_design(scene);
    TaylorTestOptions options = scene.inverse->gradcheck;
    if (args.seed) options.seed = *args.seed;
    const TaylorTestResult r = taylor_test(*design.functional, Vector::Zero(design.num_design()), options);
    out << "Taylor test of the reduced design functional (r = " << design.basis.cols()
        << ", m = " << design.num_design() << ") at w = 0\n"
        << r.table() << to_string(r.status) << ": " << r.message << "\n";
    return exit_code(r.passed());
  }
  return report_gradcheck(gradcheck_scene(scene, output_folder(file, args), {args.seed, args.hessian}, &out), out);
}

// A dynamic scene without an inverse section checks the time-dependent adjoint of its
// dynamics.objective; with one, the inverse problem's gradient.
int gradcheck_dynamic(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  const Scene scene = load_scene(file, args, out);
  if (scene.inverse)
    return report_gradcheck(gradcheck_scene(scene, output_folder(file, args), {args.seed, args.hessian}, &out),
                            out);
  refuse_hessian_flag(file, args, "the time-dependent adjoint's functionals (dynamics.objective)");
  return report_gradcheck(gradcheck_dynamic_scene(scene, output_folder(file, args), args.seed.value_or(1), &out),
                          out);
}

int run_inverse(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  const Scene scene = load_scene(file, args, out);
  if (scene.inverse && scene.inverse->design.reduction) {
    // The reduced design loop (problems/fem/reduced_design.hpp): no checkpoints.
    if (args.resume || args.checkpoint_every)
      throw SceneError(scene.source + ": " + scene.inverse->design.reduction->key +
                       ": --resume and --checkpoint-every are not supported by the reduced design loop");
    const ReducedDesignRun run =
        run_reduced_design_scene(scene, output_folder(file, args), &out, args.quiet ? nullptr : &out);
    return exit_code(run.result.converged() || run.result.status == OptimizerStatus::max_iterations);
  }
  const InverseRun run =
      run_inverse_scene(scene, output_folder(file, args), &out, args.quiet ? nullptr : &out, {args.checkpoint_every, args.resume});
  return exit_code(run.result.converged());
}

int compute_modes(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  const Scene scene = load_scene(file, args, out);
  modes_scene(scene, args.count, output_folder(file, args), &out);
  return kExitSuccess;
}

// ---- the other kinds: each parses file.node() (errors name the source and the key path), with
// relative paths from file.directory(), names the scene file.name() and writes into
// output_folder(file, args).

// Checkpoints are kept by the FEM inverse problem's optimizer only; every other run refuses the
// flags and names itself, so that a scene which has an optimizer section is not told it lacks one.
void refuse_checkpoint_flags(const VerbArguments& args, const std::string& run) {
  if (args.resume || args.checkpoint_every)
    throw UsageError("--resume and --checkpoint-every are not implemented for " + run +
                     " (only for FEM scenes with an \"inverse\" section)");
}

RigidSceneSpec load_rigid_scene(const SceneFile& file) {
  RigidSceneSpec spec = parse_rigid_scene(file.node(), file.directory());
  spec.name = file.name();
  return spec;
}

int simulate_rigid(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  return exit_code(simulate_rigid_scene(load_rigid_scene(file), output_folder(file, args), &out).completed());
}

int gradcheck_rigid(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  refuse_hessian_flag(file, args, "the design functionals of rigid-body scenes");
  return exit_code(
      gradcheck_rigid_scene(load_rigid_scene(file), output_folder(file, args), args.seed.value_or(1), &out)
          .passed());
}

// ---- periodic interlocking cells (docs/interlocking.md)

InterlockingScene load_interlocking_scene(const SceneFile& file) {
  InterlockingScene scene = parse_interlocking_scene(file.node());
  scene.name = file.name();
  return scene;
}

int simulate_interlocking(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  const InterlockingScene scene = load_interlocking_scene(file);
  return exit_code(run_interlocking_boundary(scene, scene.cell, output_folder(file, args), &out));
}

int gradcheck_interlocking(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  refuse_hessian_flag(file, args, "interlocking limit designs");
  const InterlockingScene scene = load_interlocking_scene(file);
  if (!scene.design) throw SceneError(file.source + ": interlocking: gradcheck needs a \"design\" section");
  return exit_code(gradcheck_interlocking_design(scene, output_folder(file, args), args.seed.value_or(1), &out));
}

int run_interlocking(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  const InterlockingScene scene = load_interlocking_scene(file);
  if (!scene.design) throw SceneError(file.source + ": interlocking: run needs a \"design\" section");
  return exit_code(run_interlocking_design(scene, output_folder(file, args), &out, args.quiet ? nullptr : &out));
}

int simulate_interlocking_macro(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  InterlockingMacroScene scene = parse_interlocking_macro_scene(file.node());
  scene.name = file.name();
  return exit_code(run_interlocking_macro(scene, output_folder(file, args), &out));
}

TorusSceneSpec load_torus_scene(const SceneFile& file) {
  TorusSceneSpec spec = parse_torus_scene(file.node());
  spec.name = file.name();
  return spec;
}

int simulate_tori(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  return exit_code(simulate_torus_scene(load_torus_scene(file), output_folder(file, args), &out).completed());
}

int gradcheck_tori(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  refuse_hessian_flag(file, args, "the design functionals of torus scenes");
  TorusGradcheckOptions options;
  options.seed = args.seed.value_or(1);
  return exit_code(
      gradcheck_torus_scene(load_torus_scene(file), output_folder(file, args), options, &out).passed());
}

int simulate_elastic_rods(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  const SceneNode root = file.node();
  // The design section is checked as well, as FEM scenes' are (a rod scene with a mesh refuses it).
  if (root.has("inverse") && !root.has("mesh")) parse_rod_inverse(root, parse_rod_scene(root));
  return exit_code(simulate_rod_scene(root, file.directory(), output_folder(file, args), &out));
}

int gradcheck_elastic_rods(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  const auto problem = build_rod_inverse(file.node(), file.name());
  return exit_code(
      gradcheck_rod_scene(*problem, output_folder(file, args), args.seed, args.hessian, &out).passed());
}

int run_elastic_rods(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  if (args.resume || args.checkpoint_every)
    throw UsageError("--resume and --checkpoint-every are not implemented for rod scenes");
  const auto problem = build_rod_inverse(file.node(), file.name());
  return exit_code(
      run_rod_inverse(*problem, output_folder(file, args), &out, args.quiet ? nullptr : &out).result.converged());
}

CellScene load_cell_scene(const SceneFile& file) {
  CellScene cell = parse_cell_scene(file.node(), file.directory());
  cell.name = file.name();
  return cell;
}

int homogenize_cell(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  const CellScene cell = load_cell_scene(file);
  if (cell.has_design) parse_metamaterial_design(file.node(), cell);  // checked, as `run` reads it
  homogenize_scene(cell, output_folder(file, args), &out);
  return kExitSuccess;
}

int design_cell(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  refuse_checkpoint_flags(args, "periodic-cell designs");
  const CellScene cell = load_cell_scene(file);
  const MetamaterialDesignSpec spec = parse_metamaterial_design(file.node(), cell);
  const MetamaterialRun run =
      run_metamaterial_design(cell, spec, output_folder(file, args), &out, args.quiet ? nullptr : &out);
  return exit_code(run.result.converged());
}

int fit_material(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  refuse_checkpoint_flags(args, "material fits");
  MaterialFitSpec spec = parse_material_fit_scene(file.node());
  spec.name = file.name();
  const MaterialFitRun fit = run_material_fit(spec, output_folder(file, args), &out, args.quiet ? nullptr : &out);
  return exit_code(fit.result.converged());
}

int design_damping(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  refuse_checkpoint_flags(args, "damping designs");
  return exit_code(run_damping_design_scene(file.node(), output_folder(file, args), &out));
}

// ---- meshless solids (docs/meshless.md, "Scenes")

MeshlessVerbOptions meshless_options(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  MeshlessVerbOptions o;
  o.name = file.name();
  o.directory = file.directory();
  o.out_dir = output_folder(file, args);
  o.seed = args.seed;
  o.hessian = args.hessian;
  o.count = args.count == 10 ? 0 : args.count;  // the default defers to the scene's modes.count
  o.progress = args.quiet ? nullptr : &out;
  return o;
}

int simulate_meshless(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  return exit_code(simulate_meshless_scene(file.node(), meshless_options(file, args, out), &out));
}

int modes_meshless(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  return exit_code(modes_meshless_scene(file.node(), meshless_options(file, args, out), &out));
}

int gradcheck_meshless(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  return exit_code(gradcheck_meshless_scene(file.node(), meshless_options(file, args, out), &out));
}

int run_meshless(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  refuse_checkpoint_flags(args, "meshless scenes");
  return exit_code(run_meshless_scene(file.node(), meshless_options(file, args, out), &out));
}

// ---- rigged bodies (docs/pose_space.md)

int simulate_rig(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  refuse_checkpoint_flags(args, "rig scenes");
  RigSceneSpec spec = parse_rig_scene(file.node(), file.directory());
  spec.name = file.name();
  return exit_code(run_rig_scene(spec, output_folder(file, args), &out).completed);
}

int gradcheck_rig(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  refuse_hessian_flag(file, args, "the marker functionals of rig_dynamics scenes");
  RigSceneSpec spec = parse_rig_scene(file.node(), file.directory());
  spec.name = file.name();
  return exit_code(gradcheck_rig_scene(spec, output_folder(file, args), args.seed.value_or(1), &out).passed());
}

int run_rig(const SceneFile& file, const VerbArguments& args, std::ostream& out) {
  refuse_checkpoint_flags(args, "rig scenes");
  RigSceneSpec spec = parse_rig_scene(file.node(), file.directory());
  spec.name = file.name();
  return exit_code(run_rig_inverse(spec, output_folder(file, args), &out).result.converged());
}

}  // namespace

std::string output_folder(const SceneFile& file, const VerbArguments& args) {
  if (args.out_dir) return *args.out_dir;
  if (args.resume && args.verb == "run") {
    const std::filesystem::path resume(*args.resume);
    return !std::filesystem::is_regular_file(resume) ? resume.string()
           : resume.has_parent_path()                ? resume.parent_path().string()
                                                     : ".";
  }
  return file.given() ? file.default_out_dir() : "out/" + builtin_cantilever().name;
}

std::vector<Verb> builtin_verbs() {
  return {
      {"simulate", "simulate [scene.json] [--out DIR]",
       "Solve the scene forward and write DIR/report.json and its result fields (.vtu; DIR\n"
       "defaults to out/<scene name>). Without a scene, run a built-in cantilever.",
       /*needs_scene=*/false, [](CLI::App& c, VerbArguments& a) { add_out(c, a); }},
      {"check", "check [scene.json] [--seed N]",
       "Check the derivatives of every energy term of the scene's model against finite\n"
       "differences at a randomly perturbed state (seed N, default 1).",
       /*needs_scene=*/false,
       [](CLI::App& c, VerbArguments& a) { add_seed(c, a, "seed of the perturbed state (default 1)"); },
       /*writes_output=*/false},
      {"gradcheck", "gradcheck scene.json [--out DIR] [--seed N] [--hessian]",
       "Taylor test of the gradient (and with --hessian of the Hessian-vector products)\n"
       "of the scene's inverse problem at its initial design; write DIR/gradcheck.json.",
       /*needs_scene=*/true,
       [](CLI::App& c, VerbArguments& a) {
         add_out(c, a);
         add_seed(c, a, "seed of the random direction (default: the scene's inverse.gradcheck.seed, else 1)");
         c.add_flag("--hessian", a.hessian, "also check Hessian-vector products");
       }},
      {"run", "run scene.json [--out DIR] [--quiet] [--checkpoint-every K] [--resume DIR]",
       "Optimize the design of the scene's inverse problem; print one line per iteration\n"
       "(none with --quiet); write DIR/report.json and DIR/result.vtu at the best design,\n"
       "and DIR/checkpoint.json every K iterations (default: the scene's\n"
       "optimizer.checkpoint_every, 10; 0 = none). --resume DIR continues from DIR's\n"
       "checkpoint (and writes into DIR unless --out is given).",
       /*needs_scene=*/true,
       [](CLI::App& c, VerbArguments& a) {
         add_out(c, a);
         c.add_flag("--quiet", a.quiet, "no progress line per iteration (the summary stays)");
         c.add_option("--checkpoint-every", a.checkpoint_every,
                      "write DIR/checkpoint.json every K iterations (0: never)")
             ->type_name("K")
             ->check(cli::integer_in(0, 1000000000));
         c.add_option("--resume", a.resume, "continue from the checkpoint in DIR (or the file)")
             ->type_name("DIR");
       }},
      {"modes", "modes scene.json [--out DIR] [--count N]",
       "Modal analysis at rest: the N lowest vibration modes (default 10), rigid-body modes\n"
       "set apart; write DIR/report.json (frequencies in Hz) and DIR/modes.vtu.",
       /*needs_scene=*/true,
       [](CLI::App& c, VerbArguments& a) {
         add_out(c, a);
         c.add_option("--count", a.count, "number of modes (default 10)")
             ->type_name("N")
             ->check(cli::integer_in(1, 100000));
       }},
      {"homogenize", "homogenize cell.json [--out DIR]",
       "Effective elasticity of a periodic cell (\"type\": \"periodic_cell\"); write\n"
       "DIR/report.json, PNG plots of E(d) and nu(d) and the cell fields per unit macro strain\n"
       "(.vtu).",
       /*needs_scene=*/true, [](CLI::App& c, VerbArguments& a) { add_out(c, a); }},
  };
}

std::vector<SceneKind> builtin_scene_kinds() {
  const auto any = [](const nlohmann::json&) { return true; };
  return {
      {"material_fit",
       "\"type\": \"material_fit\" (docs/materials.md)",
       [](const nlohmann::json& d) { return has_type(d, "material_fit"); },
       {{"run", fit_material, "fit a principal-stretch spline material to the scene's curves"}}},
      {"rig_dynamics",
       "a \"rig_dynamics\" section (docs/pose_space.md)",
       [](const nlohmann::json& d) { return has_section(d, "rig_dynamics"); },
       {{"simulate", simulate_rig, "a rigged arm's dynamics on its moving rest shape (full or pose-space reduced)"},
        {"gradcheck", gradcheck_rig, "Taylor test of a marker trajectory's gradient in log Young's modulus per region"},
        {"run", run_rig, "recover log Young's modulus per region from a marker's motion (an \"inverse\" section)"}}},
      {"damping_design",
       "a \"damping_design\" section (docs/dynamics.md)",
       [](const nlohmann::json& d) { return has_section(d, "damping_design"); },
       {{"run", design_damping, "the example-based damping study"}}},
      {"rigid_bodies",
       "a \"rigid_bodies\" section (docs/contact.md)",
       [](const nlohmann::json& d) { return has_section(d, "rigid_bodies"); },
       {{"simulate", simulate_rigid,
         "static equilibrium, or implicit Euler steps, of rigid bodies in contact"},
        {"gradcheck", gradcheck_rigid, "Taylor test of the body centres' gradient in the body masses"}}},
      {"tori",
       "a \"tori\" section (docs/tori.md)",
       [](const nlohmann::json& d) { return has_section(d, "tori"); },
       {{"simulate", simulate_tori,
         "a hanging chain of tori (implicit or mesh contact), static or implicit Euler steps"},
        {"gradcheck", gradcheck_tori,
         "static, implicit contact: Taylor test of the link centres' gradient in the masses and radii"}}},
      {"interlocking",
       "an \"interlocking\" section (docs/interlocking.md)",
       [](const nlohmann::json& d) { return has_section(d, "interlocking"); },
       {{"simulate", simulate_interlocking, "the strain-space boundary of a periodic interlocking cell"},
        {"gradcheck", gradcheck_interlocking, "Taylor test of the limit design functional"},
        {"run", run_interlocking, "design element radii for target deformation limits, then re-sweep"}}},
      {"macro_sheet",
       "an \"interlocking_macro\" section (docs/interlocking.md)",
       [](const nlohmann::json& d) { return has_section(d, "interlocking_macro"); },
       {{"simulate", simulate_interlocking_macro, "drape the macro-scale interlocking sheet over a sphere"}}},
      {"rods",
       "a \"rods\" section (docs/rods.md)",
       [](const nlohmann::json& d) { return has_section(d, "rods"); },
       {{"simulate", simulate_elastic_rods, "equilibrium or dynamics of discrete elastic rods"},
        {"gradcheck", gradcheck_elastic_rods,
         "needs an \"inverse\" section: Taylor test of the rod design's gradient"},
        {"run", run_elastic_rods, "needs an \"inverse\" section: rest-shape or stiffness design of a rod"}}},
      {"cell_design",
       "\"type\": \"periodic_cell\" with a \"design\" section (docs/homogenization.md)",
       [](const nlohmann::json& d) { return has_type(d, "periodic_cell") && has_section(d, "design"); },
       {{"run", design_cell, "design the cell's material layout"},
        {"homogenize", homogenize_cell, "the effective elasticity of the cell as given"}}},
      {"periodic_cell",
       "\"type\": \"periodic_cell\" (docs/homogenization.md)",
       [](const nlohmann::json& d) { return has_type(d, "periodic_cell"); },
       {{"homogenize", homogenize_cell, "the effective elasticity of the cell"}}},
      {"meshless",
       "a \"meshless\" section (docs/meshless.md)",
       [](const nlohmann::json& d) { return has_section(d, "meshless"); },
       {{"simulate", simulate_meshless, "static equilibrium of a meshless (MLS) solid: report.json, nodes.vtu, samples.vtu"},
        {"modes", modes_meshless, "modal analysis with Rayleigh damping and warped modal dynamics"},
        {"gradcheck", gradcheck_meshless, "needs an \"inverse\" section: Taylor test of the design gradient"},
        {"run", run_meshless, "needs an \"inverse\" section: Young's modulus per node or region"}}},
      {"dynamic",
       "a \"dynamics\" section (docs/dynamics.md)",
       [](const nlohmann::json& d) { return has_section(d, "dynamics"); },
       {{"simulate", simulate_dynamic, "time integration: DIR/result.pvd, DIR/frames/ and DIR/report.json"},
        {"check", check_model, ""},
        {"gradcheck", gradcheck_dynamic,
         "without an \"inverse\" section: the time-dependent adjoint of dynamics.objective"},
        {"run", run_inverse, ""},
        {"modes", compute_modes, ""}}},
      {"static",
       "any other scene (docs/scenes.md); also the built-in cantilever",
       any,
       {{"simulate", simulate_static, "static equilibrium: DIR/report.json and DIR/result.vtu"},
        {"check", check_model, ""},
        {"gradcheck", gradcheck_inverse, "needs an \"inverse\" section"},
        {"run", run_inverse, "needs an \"inverse\" section"},
        {"modes", compute_modes, ""}}},
  };
}

}  // namespace tailor
