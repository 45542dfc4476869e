#include "problems/dynamic_scene.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>

#include "adjoint/taylor_test.hpp"
#include "adjoint/transient_functional.hpp"
#include "forward/core/timing.hpp"
#include "forward/dynamics/setup.hpp"
#include "forward/fem/loads.hpp"
#include "forward/mesh/mesh_io.hpp"
#include "problems/report.hpp"
#include "problems/scene_node.hpp"
#include "problems/scene_parsing.hpp"
#include "problems/scene_selection.hpp"
#include "problems/static_scene.hpp"

namespace tailor {
namespace {

using Json = nlohmann::ordered_json;

struct StepRecord {
  int step;
  double time, kinetic, potential, seconds, residual;
  int newton_iterations;
};

Eigen::MatrixXd as_rows(const Vector& x, int dim) {
  return Eigen::Map<const Eigen::MatrixXd>(x.data(), dim, x.size() / dim).transpose();
}

}  // namespace

DynamicsSpec parse_dynamics_section(const SceneNode& node, const std::string& directory) {
  node.expect_keys(
      {"scheme", "time_step", "steps", "mass", "rayleigh", "output_every", "initial_velocity", "objective"});
  DynamicsSpec d;
  if (auto v = node.find("scheme"))
    d.scheme = parse_time_scheme(v->choice({"implicit_euler", "newmark", "bdf2"}));
  d.time_step = node.at("time_step").positive();
  d.steps = node.at("steps").integer(1);
  if (auto v = node.find("mass"))
    d.lumping =
        v->choice({"consistent", "lumped"}) == "lumped" ? MassLumping::lumped : MassLumping::consistent;
  if (auto r = node.find("rayleigh")) {
    r->expect_keys({"alpha", "beta"});
    if (auto a = r->find("alpha")) d.rayleigh_alpha = a->non_negative();
    if (auto b = r->find("beta")) d.rayleigh_beta = b->non_negative();
  }
  if (auto v = node.find("output_every")) d.output_every = v->integer(1);
  if (auto v = node.find("initial_velocity")) d.initial_velocity = v->vector();
  if (auto o = node.find("objective")) {
    o->expect_keys({"vertices", "quantity", "steps", "target"});
    TrajectoryTargetSpec t;
    t.key = o->path();
    t.vertices = parse_vertex_selector(o->at("vertices"), directory);
    if (auto q = o->find("quantity"))
      t.quantity = q->choice({"position", "velocity"}) == "velocity" ? TrajectoryQuantity::velocity
                                                                     : TrajectoryQuantity::position;
    if (auto steps = o->find("steps")) {
      t.steps = steps->integers(1);
      for (int step : t.steps)
        if (step > d.steps)
          steps->fail("step " + std::to_string(step) + " is beyond the last step " + std::to_string(d.steps));
    }
    t.target = o->at("target").vector();
    d.objective = t;
  }
  return d;
}

namespace {

// The model of a dynamic scene: the static scene's model plus inertia and Rayleigh damping.
struct DynamicSceneModel {
  StaticSetup setup;
  std::unique_ptr<Model> model;
  DynamicTerms terms;
  Vector p, rest, initial_positions, initial_velocities;
  TimeIntegratorOptions options;
  bool rayleigh = false;
};

DynamicSceneModel build_dynamic_scene(const Scene& scene) {
  const DynamicsSpec& spec = *scene.dynamics;
  DynamicSceneModel d;
  d.setup = setup_static_scene(scene);
  const int dim = d.setup.dim(), m = d.setup.mesh.num_elements();
  for (std::size_t k = 0; k < scene.materials.size(); ++k)
    if (!(scene.materials[k].density > 0.0))
      throw SceneError(scene.source + ": " + scene.materials[k].key +
                       ".density: a dynamic scene needs a positive density");
  if (spec.initial_velocity && spec.initial_velocity->size() != dim)
    throw SceneError(scene.source + ": dynamics.initial_velocity: expected " + std::to_string(dim) +
                     " components");
  // Gravity becomes a GravityTerm of the density parameters (so that designs of the density
  // move the weight too) instead of part of the static setup's dead load.
  if (scene.loads.gravity)
    d.setup.nodal_forces -= gravity_forces(d.setup.mesh, d.setup.density, *scene.loads.gravity);
  d.model = build_static_model(d.setup, 1.0);
  d.rayleigh = spec.rayleigh_alpha > 0.0 || spec.rayleigh_beta > 0.0;
  d.terms = add_dynamics_terms(*d.model, d.setup.mesh,
                               DynamicsSetup{spec.lumping, scene.loads.gravity, d.rayleigh});
  d.p.resize(d.model->parameter_layout().size());
  d.p.head(2 * m) = d.setup.parameters();
  d.p.segment(d.terms.density_offset, m) = d.setup.density;
  if (d.rayleigh)
    d.p[d.terms.alpha_offset] = spec.rayleigh_alpha, d.p[d.terms.beta_offset] = spec.rayleigh_beta;
  d.options.scheme = spec.scheme;
  d.options.time_step = spec.time_step;
  d.options.newton.max_iterations = std::max(d.setup.solver.newton.max_iterations, 1);
  d.options.newton.hessian = d.setup.solver.newton.hessian;
  d.rest = d.setup.rest_state();
  d.initial_velocities = Vector::Zero(d.rest.size());
  if (spec.initial_velocity)
    for (int v = 0; v < d.setup.mesh.num_vertices(); ++v)
      d.initial_velocities.segment(dim * v, dim) = *spec.initial_velocity;
  // Rest positions with the prescribed values on the fixed DOFs.
  d.initial_positions = d.model->elimination().expand(d.model->elimination().restrict_state(d.rest));
  return d;
}

}  // namespace

DynamicRun simulate_dynamic_scene(const Scene& scene, const std::string& out_dir, std::ostream* log) {
  const auto t_start = Clock::now();
  const DynamicsSpec& spec = *scene.dynamics;
  DynamicSceneModel d = build_dynamic_scene(scene);
  const StaticSetup& setup = d.setup;
  const int dim = setup.dim();
  const Vector& p = d.p;
  const Vector& rest = d.rest;
  TimeIntegrator integrator(*d.model, d.options);
  DynamicState state = integrator.initial_state(d.initial_positions, d.initial_velocities, p);
  const double setup_seconds = seconds_since(t_start);
  if (log)
    *log << "dynamic scene '" << scene.name << "': " << setup.mesh.num_elements() << " elements, "
         << d.model->elimination().num_free() << " free DOFs; " << to_string(spec.scheme)
         << ", h = " << spec.time_step << ", " << spec.steps << " steps\n";

  std::error_code error;
  const std::filesystem::path out(out_dir), frames = out / "frames";
  std::filesystem::create_directories(frames, error);
  if (error)
    throw std::runtime_error("cannot create the output folder '" + frames.string() + "': " + error.message());

  DynamicRun run;
  std::vector<StepRecord> records;
  std::vector<std::pair<double, std::string>> written;
  double output_seconds = 0.0;
  auto write_frame = [&](const DynamicState& s) {
    const auto t0 = Clock::now();
    std::ostringstream name;
    name << "frame_" << std::setw(5) << std::setfill('0') << s.step << ".vtu";
    VtkFields fields;
    fields.point["displacement"] = as_rows(s.x - rest, dim);
    fields.point["velocity"] = as_rows(s.v, dim);
    fields.cell["youngs_modulus"] = setup.youngs_modulus;
    const Eigen::MatrixXd positions = as_rows(s.x, dim);
    write_vtu((frames / name.str()).string(), setup.mesh, fields, &positions);
    written.emplace_back(s.time, "frames/" + name.str());
    output_seconds += seconds_since(t0);
  };
  auto record = [&](const DynamicState& s, const NewtonResult* r, double seconds) {
    records.push_back({s.step, s.time, integrator.kinetic_energy(s.v, p), integrator.potential_energy(s.x, p),
                       seconds, r ? r->final_residual : 0.0, r ? r->iterations : 0});
  };
  record(state, nullptr, 0.0);
  write_frame(state);
  run.completed = true;
  run.message = "all steps converged";
  for (int n = 0; n < spec.steps; ++n) {
    const auto t0 = Clock::now();
    const NewtonResult r = integrator.step(state, p);
    if (!r.converged()) {
      run.completed = false;
      run.message =
          "step " + std::to_string(n + 1) + " failed: " + to_string(r.status) + " (" + r.message + ")";
      break;
    }
    record(state, &r, seconds_since(t0));
    if (state.step % spec.output_every == 0 || state.step == spec.steps) write_frame(state);
    if (log && (state.step % std::max(1, spec.steps / 10) == 0 || state.step == spec.steps))
      *log << "  step " << state.step << "/" << spec.steps << "  t " << state.time << "  Newton "
           << r.iterations << "  E " << std::scientific << std::setprecision(4)
           << records.back().kinetic + records.back().potential << std::defaultfloat << "\n";
  }
  run.steps_done = state.step;

  run.series_path = (out / "result.pvd").string();
  {
    std::ofstream pvd(run.series_path);
    pvd << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n";
    for (const auto& [time, file] : written)
      pvd << "    <DataSet timestep=\"" << std::setprecision(17) << time << "\" file=\"" << file << "\"/>\n";
    pvd << "  </Collection>\n</VTKFile>\n";
    if (!pvd) throw std::runtime_error("cannot write '" + run.series_path + "'");
  }
  Json report;
  add_report_header(report);
  report["scene"] = {{"name", scene.name}, {"source", scene.source}};
  report["kind"] = "dynamics";
  report["status"] = run.completed ? "completed" : "failed";
  report["message"] = run.message;
  report["dynamics"] = {{"scheme", to_string(spec.scheme)},
                        {"time_step", spec.time_step},
                        {"steps", spec.steps},
                        {"steps_done", run.steps_done},
                        {"mass", spec.lumping == MassLumping::lumped ? "lumped" : "consistent"},
                        {"rayleigh_alpha", spec.rayleigh_alpha},
                        {"rayleigh_beta", spec.rayleigh_beta}};
  Json steps = Json::array();
  double step_seconds = 0.0;
  for (const StepRecord& r : records) {
    step_seconds += r.seconds;
    steps.push_back({{"step", r.step},
                     {"time", r.time},
                     {"newton_iterations", r.newton_iterations},
                     {"final_residual", r.residual},
                     {"kinetic_energy", r.kinetic},
                     {"potential_energy", r.potential},
                     {"total_energy", r.kinetic + r.potential},
                     {"seconds", r.seconds}});
  }
  report["steps"] = steps;
  report["timings"] = {{"total", seconds_since(t_start)},
                       {"setup", setup_seconds},
                       {"steps", step_seconds},
                       {"output", output_seconds}};
  report["series"] = "result.pvd";
  run.report_path = (out / "report.json").string();
  std::ofstream file(run.report_path);
  file << report.dump(2) << "\n";
  if (!file) throw std::runtime_error("cannot write '" + run.report_path + "'");
  if (log)
    *log << (run.completed ? "completed " : "FAILED: ") << run.message << "; wrote " << run.report_path
         << " and " << run.series_path << " (" << written.size() << " frames)\n";
  return run;
}

}  // namespace tailor

namespace tailor {

GradcheckRun gradcheck_dynamic_scene(const Scene& scene, const std::string& out_dir, unsigned seed,
                                     std::ostream* log) {
  const DynamicsSpec& spec = *scene.dynamics;
  if (!spec.objective)
    throw SceneError(scene.source + ": dynamics.objective: gradcheck needs a trajectory objective");
  const TrajectoryTargetSpec& target = *spec.objective;
  DynamicSceneModel d = build_dynamic_scene(scene);
  const Mesh& mesh = d.setup.mesh;
  const int dim = d.setup.dim(), m = mesh.num_elements();
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
  auto objective = std::make_shared<KeyframeTargets>(dim, vertices, target.quantity, frames);
  // Design: log E and log density per element, and alpha, beta with Rayleigh damping.
  std::vector<ParameterBlock> blocks{{0, exp_map(m)}, {d.terms.density_offset, exp_map(m)}};
  if (d.rayleigh) blocks.push_back({d.terms.alpha_offset, identity_map(2)});
  const ParameterizationPtr map = embed_blocks(d.p, blocks);
  Vector z0(map->num_design());
  z0.head(m) = d.p.head(m).array().log().matrix();
  z0.segment(m, m) = d.p.segment(d.terms.density_offset, m).array().log().matrix();
  if (d.rayleigh) z0.tail(2) << d.p[d.terms.alpha_offset], d.p[d.terms.beta_offset];

  TimeIntegrator integrator(*d.model, d.options);
  TransientFunctionalOptions options;
  options.steps = spec.steps;
  TransientFunctional functional(integrator, map, objective, d.initial_positions, d.initial_velocities,
                                 options);
  TaylorTestOptions taylor;
  taylor.seed = seed;
  GradcheckRun run;
  run.scene_name = scene.name;
  run.scene_source = scene.source;
  run.design_size = static_cast<int>(z0.size());
  run.seed = seed;
  run.gradient = taylor_test(functional, z0, taylor);
  std::error_code error;
  std::filesystem::create_directories(out_dir, error);
  if (error)
    throw std::runtime_error("cannot create the output folder '" + out_dir + "': " + error.message());
  run.report_path = (std::filesystem::path(out_dir) / "gradcheck.json").string();
  write_gradcheck_json(run.report_path, run);
  if (log)
    *log << "Taylor test of the time-dependent adjoint over " << spec.steps << " steps ("
         << to_string(spec.scheme) << "), " << run.design_size << " design variables (log E, log density"
         << (d.rayleigh ? ", alpha, beta" : "") << "), seed " << seed << ":\n"
         << run.gradient.table() << "wrote " << run.report_path << "\n";
  return run;
}

}  // namespace tailor
