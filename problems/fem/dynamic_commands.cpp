#include "problems/fem/dynamic_commands.hpp"

#include <filesystem>
#include <iomanip>
#include <optional>
#include <ostream>

#include "adjoint/taylor_test.hpp"
#include "adjoint/transient_functional.hpp"
#include "forward/dynamics/descent_time_stepper.hpp"
#include "forward/core/format_number.hpp"
#include "forward/core/timing.hpp"
#include "problems/fem/physics_warnings.hpp"
#include "problems/fem/reduced_dynamic_run.hpp"
#include "problems/fem/scene_selection.hpp"
#include "problems/output_process.hpp"
#include "problems/scene_error.hpp"

namespace tailor {
namespace {

void create_folder(const std::filesystem::path& folder) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error)
    throw std::runtime_error("cannot create the output folder '" + folder.string() + "': " + error.message());
}

// The scene's trajectory objective: its targets at the listed steps (default: the last).
std::shared_ptr<KeyframeTargets> trajectory_objective(const Scene& scene, const DynamicSceneModel& d) {
  const DynamicsSpec& spec = *scene.dynamics;
  const TrajectoryTargetSpec& target = *spec.objective;
  const Mesh& mesh = d.setup.mesh;
  const int dim = d.setup.dim();
  check_dimension(scene, mesh, target.target, target.key + ".target");
  const std::vector<int> vertices = select_vertices(scene, mesh, target.vertices);
  std::vector<Keyframe> frames;
  for (int step : target.steps.empty() ? std::vector<int>{spec.steps} : target.steps) {
    Matrix t(vertices.size(), dim);
    for (std::size_t i = 0; i < vertices.size(); ++i)
      t.row(i) = target.quantity == TrajectoryQuantity::position
                     ? Eigen::RowVectorXd(mesh.rest_positions.row(vertices[i]) + target.target.transpose())
                     : Eigen::RowVectorXd(target.target.transpose());
    frames.push_back({step, t, 1.0});
  }
  return std::make_shared<KeyframeTargets>(dim, vertices, target.quantity, frames);
}

// The frames' disk use, projected from the first frame's file: printed; a warning above 1 GB; a
// SceneError (exit 2, before any step) when it would not fit the free space of the disk.
void check_output_size(const Scene& scene, const std::filesystem::path& first_frame, std::ostream* log) {
  const DynamicsSpec& spec = *scene.dynamics;
  std::error_code ec;
  const double frame_bytes = static_cast<double>(std::filesystem::file_size(first_frame, ec));
  if (ec) return;
  const long frames = 1 + spec.steps / spec.output_every + (spec.steps % spec.output_every != 0 ? 1 : 0);
  const double total = frame_bytes * static_cast<double>(frames);
  const std::filesystem::space_info space = std::filesystem::space(first_frame.parent_path(), ec);
  const auto gb = [](double bytes) { return format_number(bytes / 1e9, "%.3g") + " GB"; };
  const std::string estimate =
      std::to_string(frames) + " frames of " + format_number(frame_bytes / 1e6, "%.3g") + " MB: " + gb(total);
  if (!ec && total > static_cast<double>(space.available))
    throw SceneError(scene.source + ": dynamics.steps / output_every: " + estimate + ", more than the " +
                     gb(static_cast<double>(space.available)) +
                     " free on the output disk; write fewer frames (a larger output_every)");
  if (log && total > 1e9)
    *log << "warning: " << scene.source << ": dynamics: the output will take " << estimate
         << "; a larger output_every writes fewer frames\n";
}

}  // namespace

DynamicRun simulate_dynamic_scene(const Scene& scene, const std::string& out_dir, std::ostream* log) {
  if (scene.dynamics->reduction) return simulate_reduced_dynamic_scene(scene, out_dir, log);
  const auto t_start = Clock::now();
  const DynamicsSpec& spec = *scene.dynamics;
  DynamicSceneModel d = build_dynamic_scene(scene);
  const StaticSetup& setup = d.setup;
  const Vector& p = d.p;
  TimeIntegrator integrator(*d.model, d.options);
  DynamicState state = integrator.initial_state(d.initial_positions, d.initial_velocities, p);
  std::optional<DescentTimeStepper> descent;
  if (spec.solver_method == "descent") try {
      descent.emplace(integrator, spec.descent);
    } catch (const std::invalid_argument& e) {
      throw SceneError(scene.source + ": dynamics.solver.method: " + e.what());
    } catch (const std::runtime_error& e) {  // "gpu" without a usable device
      throw SceneError(scene.source + ": dynamics.solver.device: " + e.what());
    }
  DynamicRun run;
  int descent_unconverged = 0;  // descent steps stopped by the budget or round-off
  run.timings.setup = seconds_since(t_start);
  if (log)
    *log << "dynamic scene '" << scene.name << "': " << setup.mesh.num_elements() << " elements, "
         << d.model->elimination().num_free() << " free DOFs; " << to_string(spec.scheme)
         << ", h = " << spec.time_step << ", " << spec.steps << " steps\n";

  run.linear_solver = d.options.newton.linear_solver;
  run.warnings = locking_warnings(scene);
  for (const std::string& warning : time_step_warnings(scene)) {
    if (log) *log << "warning: " << warning << "\n";
    run.warnings.push_back(warning);
  }
  // Every MPI rank of a replicated run (docs/petsc.md) steps the same states; rank 0 writes.
  const bool writes = writes_output();
  const std::filesystem::path out(out_dir), frames = out / "frames";
  if (writes) create_folder(frames);
  auto write_frame = [&](const DynamicState& s) {
    const auto t0 = Clock::now();
    run.frames.emplace_back(s.time, writes ? write_dynamic_frame(frames, setup, d.rest, s) : std::string());
    run.timings.output += seconds_since(t0);
  };
  auto record = [&](const DynamicState& s, double residual, int iterations, double seconds) {
    run.records.push_back({s.step, s.time, integrator.kinetic_energy(s.v, p),
                           integrator.potential_energy(s.x, p), seconds, residual, iterations});
  };
  record(state, 0.0, 0, 0.0);
  write_frame(state);
  if (writes) check_output_size(scene, out / run.frames.front().second, log);
  run.completed = true;
  run.message = "all steps converged";
  for (int n = 0; n < spec.steps; ++n) {
    const auto t0 = Clock::now();
    int iterations = 0;
    if (descent) {
      // A step stopped by the iteration budget is taken: its residual is in the report.
      const DescentResult r = descent->step(state, p);
      if (!r.usable()) {
        run.completed = false;
        run.message =
            "step " + std::to_string(n + 1) + " failed: " + to_string(r.status) + " (" + r.message + ")";
        break;
      }
      iterations = r.iterations;
      if (!r.converged()) ++descent_unconverged;
      record(state, r.final_residual, r.iterations, seconds_since(t0));
    } else {
      const NewtonResult r = integrator.step(state, p);
      if (!r.converged()) {
        run.completed = false;
        run.message =
            "step " + std::to_string(n + 1) + " failed: " + to_string(r.status) + " (" + r.message + ")";
        break;
      }
      iterations = r.iterations;
      record(state, r.final_residual, r.iterations, seconds_since(t0));
    }
    if (state.step % spec.output_every == 0 || state.step == spec.steps) write_frame(state);
    if (log && (state.step % std::max(1, spec.steps / 10) == 0 || state.step == spec.steps))
      *log << "  step " << state.step << "/" << spec.steps << "  t " << state.time
           << (descent ? "  descent " : "  Newton ") << iterations << "  E " << std::scientific << std::setprecision(4)
           << run.records.back().kinetic + run.records.back().potential << std::defaultfloat << "\n";
  }
  run.steps_done = state.step;
  if (run.completed && descent_unconverged > 0)
    run.message = "all steps done; " + std::to_string(descent_unconverged) +
                  " descent steps stopped before the tolerance (by the iteration budget or the energy's "
                  "round-off), their residuals are in the report";

  run.series_path = (out / "result.pvd").string();
  if (writes) write_dynamic_series(run.series_path, run);
  run.report_path = (out / "report.json").string();
  run.timings.total = seconds_since(t_start);
  if (writes) write_dynamic_report_json(run.report_path, scene, run);
  if (log)
    *log << (run.completed ? "completed " : "FAILED: ") << run.message << "; wrote " << run.report_path
         << " and " << run.series_path << " (" << run.frames.size() << " frames)\n";
  return run;
}

std::unique_ptr<DynamicDesign> build_dynamic_design(const Scene& scene) {
  const DynamicsSpec& spec = *scene.dynamics;
  if (!spec.objective)
    throw SceneError(scene.source + ": dynamics.objective: a trajectory design needs a trajectory objective");
  // The transient adjoint differentiates the step equations at their solutions, which descent
  // reaches only to its tolerance; re-solving every step by Newton would make the trajectory
  // Newton's, so the scene's method would not be what is differentiated.
  if (spec.solver_method == "descent")
    throw SceneError(scene.source +
                     ": dynamics.solver.method: the transient adjoint needs each step solved by Newton (it "
                     "differentiates the step equations at their exact solutions, and descent stops at its "
                     "tolerance or iteration budget); use \"method\": \"newton\" for gradcheck and functional()");
  if (spec.reduction)
    throw SceneError(scene.source + ": " + spec.reduction->key +
                     ": gradcheck and functional() differentiate the full-space steps (the transient adjoint); "
                     "remove the reduction section for them");
  auto design = std::make_unique<DynamicDesign>();
  design->scene_model = build_dynamic_scene(scene);
  DynamicSceneModel& d = design->scene_model;
  const int m = d.setup.mesh.num_elements();
  auto objective = trajectory_objective(scene, d);
  std::vector<ParameterBlock> blocks{{0, exp_map(m)}, {d.terms.density_offset, exp_map(m)}};
  if (d.rayleigh) blocks.push_back({d.terms.alpha_offset, identity_map(2)});
  design->parameterization = embed_blocks(d.p, blocks);
  Vector& z0 = design->z0;
  z0.resize(design->parameterization->num_design());
  z0.head(m) = d.p.head(m).array().log().matrix();
  z0.segment(m, m) = d.p.segment(d.terms.density_offset, m).array().log().matrix();
  if (d.rayleigh) z0.tail(2) << d.p[d.terms.alpha_offset], d.p[d.terms.beta_offset];
  for (int e = 0; e < m; ++e) design->labels.push_back("log_youngs_modulus[" + std::to_string(e) + "]");
  for (int e = 0; e < m; ++e) design->labels.push_back("log_density[" + std::to_string(e) + "]");
  if (d.rayleigh) design->labels.insert(design->labels.end(), {"rayleigh_alpha", "rayleigh_beta"});

  design->integrator = std::make_unique<TimeIntegrator>(*d.model, d.options);
  TransientFunctionalOptions options;
  options.steps = design->steps = spec.steps;
  design->functional =
      std::make_unique<TransientFunctional>(*design->integrator, design->parameterization, objective,
                                            d.initial_positions, d.initial_velocities, options);
  return design;
}

GradcheckRun gradcheck_dynamic_scene(const Scene& scene, const std::string& out_dir, unsigned seed,
                                     std::ostream* log) {
  const DynamicsSpec& spec = *scene.dynamics;
  if (!spec.objective)
    throw SceneError(scene.source + ": dynamics.objective: gradcheck needs a trajectory objective");
  const auto design = build_dynamic_design(scene);
  const DynamicSceneModel& d = design->scene_model;
  TransientFunctional& functional = *design->functional;
  const Vector& z0 = design->z0;
  const TransientFunctionalOptions options;  // the functional's: its linear tolerance is reported
  TaylorTestOptions taylor;
  taylor.seed = seed;
  GradcheckRun run;
  run.scene_name = scene.name;
  run.scene_source = scene.source;
  run.design_size = static_cast<int>(z0.size());
  run.seed = seed;
  run.gradient = taylor_test(functional, z0, taylor);
  run.linear_solver = d.options.newton.linear_solver;
  if (run.linear_solver) {
    const TransientStatistics& stats = functional.statistics();
    run.adjoint_linear_solves =
        AdjointLinearSolves{options.linear_relative_tolerance, stats.linear_solver_solves,
                            stats.linear_solver_iterations, stats.last_linear_solve.relative_residual};
  }
  run.report_path = (std::filesystem::path(out_dir) / "gradcheck.json").string();
  if (writes_output()) {
    create_folder(out_dir);
    write_gradcheck_json(run.report_path, run);
  }
  if (log)
    *log << "Taylor test of the time-dependent adjoint over " << spec.steps << " steps ("
         << to_string(spec.scheme) << "), " << run.design_size << " design variables (log E, log density"
         << (d.rayleigh ? ", alpha, beta" : "") << "), seed " << seed << ":\n"
         << run.gradient.table() << "wrote " << run.report_path << "\n";
  return run;
}

}  // namespace tailor
