#include "problems/fem/inverse_commands.hpp"

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <ostream>

#include "forward/core/timing.hpp"
#include "problems/optimizer_checkpoint.hpp"
#include "problems/output_process.hpp"
#include "problems/plot/convergence_plot.hpp"
#include "problems/scene_error.hpp"
#include "problems/plot/field_image.hpp"

namespace tailor {
namespace {

// The path of an output file, its folder created when this process writes files (rank 0 of a
// replicated MPI run, problems/output_process.hpp).
std::string output_path(const std::string& out_dir, const char* name) {
  if (!writes_output()) return (std::filesystem::path(out_dir) / name).string();
  std::error_code error;
  std::filesystem::create_directories(out_dir, error);
  if (error)
    throw std::runtime_error("cannot create the output folder '" + out_dir + "': " + error.message());
  return (std::filesystem::path(out_dir) / name).string();
}

std::string design_formula(const DesignSpec& d) {
  if (d.granularity != DesignGranularity::modes) return d.map == DesignMap::log ? "z = log E" : "z = E";
  const std::string y = d.modes ? "y = Phi z + y0" : "y = z";
  if (!d.min) return y + ", E = exp(y)";
  return y + (d.map == DesignMap::log ? ", log E in the smooth box (log min, log max) of y"
                                      : ", E in the smooth box (min, max) of y");
}

// What a checkpoint of this problem must match to be resumed here.
CheckpointOwner checkpoint_owner(const InverseProblem& problem) {
  const Mesh& mesh = problem.setup.mesh;
  const DesignSpec& d = problem.spec.design;
  std::string description = std::to_string(mesh.dim()) + "D mesh, " + std::to_string(mesh.num_vertices()) +
                            " vertices, " + std::to_string(mesh.num_elements()) + " elements; design " +
                            d.parameter + " " + to_string(d.granularity) + " (" + to_string(d.map) + "), " +
                            std::to_string(problem.num_material_design()) + " material variables";
  if (problem.handles)
    description += " and " + std::to_string(problem.handles->size()) + " handle displacements";
  return {"inverse", problem.scene_name, problem.scene_source, problem.num_design(), description};
}

void print_problem(std::ostream& log, const InverseProblem& problem) {
  const DesignSpec& d = problem.spec.design;
  const Mesh& mesh = problem.setup.mesh;
  log << "scene '" << problem.scene_name << "' (" << problem.scene_source << "): " << mesh.dim() << "D mesh, "
      << mesh.num_vertices() << " vertices, " << mesh.num_elements() << " elements; design: " << d.parameter
      << " " << (problem.element_map ? "element_map" : to_string(d.granularity)) << " ("
      << problem.num_material_design() << " variable" << (problem.num_material_design() == 1 ? "" : "s")
      << "), " << (problem.element_map ? "E = " + problem.element_map->name() + "(z)" : design_formula(d));
  if (problem.handles) log << ", plus " << problem.handles->size() << " handle displacements";
  log << "\n";
  if (problem.modal && d.modes)
    log << "material modes: " << *d.modes << " in " << std::fixed << std::setprecision(3)
        << problem.modal->seconds << " s (" << problem.modal->eigen_message << ")" << std::defaultfloat
        << "\n";
  log << "objective:";
  for (const ObjectiveTermInfo& t : problem.terms)
    log << (&t == &problem.terms.front() ? " " : " + ") << std::defaultfloat << std::setprecision(4)
        << t.coefficient << " * " << t.type;
  log << "\n";
}

// Design values one per line for small designs (per region or material), a summary otherwise.
void print_design(std::ostream& log, const InverseRun& run) {
  const InverseProblem& problem = *run.problem;
  log << std::scientific << std::setprecision(8);
  if (problem.spec.design.grouped()) {
    const Eigen::VectorXd initial = problem.design_values(problem.z0);
    for (int k = 0; k < problem.num_material_design(); ++k)
      log << "  " << problem.design_labels[k] << ": E = " << run.design_values[k] << " (initial "
          << initial[k] << ")\n";
  } else {
    log << "  E per element: min " << run.youngs_modulus.minCoeff() << ", max "
        << run.youngs_modulus.maxCoeff() << "\n";
  }
  if (run.error)
    log << "  error against the ground truth (" << problem.truth_key << "): relative L2 "
        << std::setprecision(3) << run.error->relative_l2 << ", max relative " << run.error->max_relative
        << " (initially " << run.initial_error->relative_l2 << ")\n";
  for (const HandleResult& h : run.handles) {
    log << "  " << h.key << " (" << h.vertices << " vertices): force " << h.total_force.transpose();
    if (h.target_force.size() > 0)
      log << ", error " << std::setprecision(3) << h.force_error << " (relative " << h.relative_force_error
          << ")" << std::setprecision(8);
    log << "; displacement " << h.displacement.transpose();
    if (h.target_displacement.size() > 0)
      log << ", error " << std::setprecision(3) << h.displacement_error << " (relative "
          << h.relative_displacement_error << ")" << std::setprecision(8);
    log << "\n";
  }
  log << std::defaultfloat;
}

}  // namespace

GradcheckRun gradcheck_scene(const Scene& scene, const std::string& out_dir,
                             const GradcheckSettings& settings, std::ostream* log) {
  const std::unique_ptr<InverseProblem> problem = build_inverse_problem(scene);
  return gradcheck_problem(*problem, out_dir, settings, log);
}

GradcheckRun gradcheck_problem(InverseProblem& built, const std::string& out_dir,
                               const GradcheckSettings& settings, std::ostream* log) {
  InverseProblem* problem = &built;
  // Refused before any solve, not after the gradient's check.
  if (settings.hessian && !problem->functional->has_hessian_vector())
    throw SceneError(problem->scene_source +
                     ": --hessian: this inverse problem has no Hessian-vector products (an objective term "
                     "without second derivatives, such as a handle's reaction force); run gradcheck "
                     "without --hessian to check its gradient");
  TaylorTestOptions options = problem->spec.gradcheck;
  if (settings.seed) options.seed = *settings.seed;
  GradcheckRun run;
  run.scene_name = problem->scene_name;
  run.scene_source = problem->scene_source;
  run.design_size = problem->num_design();
  run.seed = options.seed;
  if (log) {
    print_problem(*log, *problem);
    *log << "gradient check at the initial design, seed " << options.seed << "\n";
  }
  // J(z + h dz) is only as accurate as the equilibrium; the Taylor test resolves remainders
  // down to its round-off, so solve to the floor (Newton stops there, round_off_floor).
  NewtonOptions& newton = problem->functional->newton_options();
  const double tighter = 1e-14 / newton.relative_tolerance;
  newton.relative_tolerance *= tighter;
  newton.absolute_tolerance *= tighter;
  run.gradient = taylor_test(*problem->functional, problem->z0, options);
  if (log) *log << run.gradient.table();
  if (settings.hessian) {
    if (log) *log << "Hessian-vector check at the initial design\n";
    run.hessian = taylor_test_hessian(*problem->functional, problem->z0, options);
    if (log) *log << run.hessian->table();
  }
  run.report_path = output_path(out_dir, "gradcheck.json");
  run.linear_solver = newton.linear_solver;
  if (writes_output()) write_gradcheck_json(run.report_path, run);
  if (log) *log << (run.passed() ? "passed" : "FAILED") << "; wrote " << run.report_path << "\n";
  return run;
}

InverseRun run_inverse_scene(const Scene& scene, const std::string& out_dir, std::ostream* log,
                             std::ostream* progress, const RunSettings& settings) {
  return run_inverse_problem(build_inverse_problem(scene), out_dir, log, progress, settings);
}

InverseRun run_inverse_problem(std::unique_ptr<InverseProblem> built, const std::string& out_dir,
                               std::ostream* log, std::ostream* progress, const RunSettings& settings,
                               const std::vector<Constraint>& constraints) {
  if (!built) throw std::invalid_argument("run_inverse_problem: no problem");
  // The setup counts as part of the run, as for run_inverse_scene.
  const auto t_start = Clock::now() - std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>(built->setup_seconds));
  InverseRun run;
  run.problem = std::move(built);
  InverseProblem& problem = *run.problem;
  run.timings.setup = problem.setup_seconds;
  if (problem.modal) run.timings.modes = problem.modal->seconds;
  if (log) print_problem(*log, problem);

  const CheckpointOwner owner = checkpoint_owner(problem);
  std::optional<CheckpointFile> resume;
  if (settings.resume) {
    resume = read_checkpoint_json(*settings.resume);
    check_checkpoint(*resume, owner, problem.spec.optimizer.backend);
    run.resumed = ResumedRun{resume->path, resume->checkpoint.iteration};
    if (log)
      *log << "resuming from " << resume->path << " at iteration " << resume->checkpoint.iteration << "\n";
  }

  OptimizerOptions options = problem.spec.optimizer;
  options.progress = progress;
  if (settings.checkpoint_every) options.checkpoint_every = *settings.checkpoint_every;
  if (options.checkpoint_every > 0) {
    run.checkpoint_path = output_path(out_dir, kCheckpointFileName);
    options.on_checkpoint = [&run, &owner](const OptimizerCheckpoint& checkpoint) {
      if (writes_output()) write_checkpoint_json(run.checkpoint_path, owner, checkpoint);
    };
  }
  run.result = minimize(*problem.functional, problem.z0, problem.bounds, constraints, options,
                        resume ? &resume->checkpoint : nullptr);
  run.timings.optimization = run.result.seconds;
  run.timings.forward = run.result.counters.forward_seconds;
  run.timings.adjoint = run.result.counters.adjoint_seconds;

  // The equilibrium at the best design, solved like `tailor simulate` would (with the scene's
  // load steps), for result.vtu and the per-term objective values.
  const auto t_output = Clock::now();
  run.design_values = problem.design_values(run.result.z);
  run.youngs_modulus = problem.youngs_modulus(run.result.z);
  const StaticSetup best = problem.setup_at(run.result.z);
  run.solution = solve_static(best);
  if (run.solution.converged) {
    const Vector p = problem.parameterization->apply(run.result.z);
    for (const ObjectiveTermInfo& t : problem.terms)
      run.term_values.push_back(t.coefficient * t.term->value(run.solution.positions, p));
    run.handles = handle_results(problem, run.result.z, run.solution.positions);
  }
  if (problem.truth.size() > 0) {
    run.error = field_error(best.mesh, run.youngs_modulus, problem.truth);
    run.initial_error = field_error(best.mesh, problem.youngs_modulus(problem.z0), problem.truth);
  }
  run.result_path = output_path(out_dir, "result.vtu");
  run.report_path = output_path(out_dir, "report.json");
  if (writes_output()) write_inverse_result_vtu(run.result_path, run);
  run.timings.output = seconds_since(t_output);
  run.timings.total = seconds_since(t_start);
  if (writes_output()) write_inverse_report_json(run.report_path, run);
  const std::string plot_path = output_path(out_dir, "convergence.png");
  if (writes_output())
    write_convergence_png(plot_path, run.result,
                          problem.scene_name + " (" + to_string(problem.spec.optimizer.backend) + ")");
  // The designed field next to the truth, on one colour scale.
  const std::string field_path = output_path(out_dir, "youngs_modulus.png");
  std::vector<FieldPanel> panels{{"designed E", run.youngs_modulus}};
  if (problem.truth.size() > 0) panels.push_back({"true E", problem.truth});
  if (writes_output()) write_field_png(field_path, problem.setup.mesh, panels, {problem.scene_name, "E"});
  if (log) {
    *log << run.result.report();
    print_design(*log, run);
    *log << "wrote " << run.report_path << ", " << run.result_path << ", " << plot_path << " and "
         << field_path;
    if (!run.checkpoint_path.empty() && std::filesystem::exists(run.checkpoint_path))
      *log << "; the last checkpoint is " << run.checkpoint_path;
    *log << "\n";
  }
  return run;
}

}  // namespace tailor
