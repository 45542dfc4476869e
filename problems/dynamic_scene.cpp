#include "problems/dynamic_scene.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>

#include "forward/dynamics/setup.hpp"
#include "forward/mesh/mesh_io.hpp"
#include "problems/report.hpp"
#include "problems/scene_node.hpp"
#include "problems/scene_parsing.hpp"
#include "problems/static_scene.hpp"
#include "tailor_version.hpp"

namespace tailor {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}
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

DynamicsSpec parse_dynamics_section(const SceneNode& node) {
  node.expect_keys({"scheme", "time_step", "steps", "mass", "rayleigh", "output_every", "initial_velocity"});
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
  return d;
}

DynamicRun simulate_dynamic_scene(const Scene& scene, const std::string& out_dir, std::ostream* log) {
  const auto t_start = Clock::now();
  const DynamicsSpec& spec = *scene.dynamics;
  const StaticSetup setup = setup_static_scene(scene);
  const int dim = setup.dim(), m = setup.mesh.num_elements();
  for (std::size_t k = 0; k < scene.materials.size(); ++k)
    if (!(scene.materials[k].density > 0.0))
      throw SceneError(scene.source + ": " + scene.materials[k].key +
                       ".density: a dynamic scene needs a positive density");
  if (spec.initial_velocity && spec.initial_velocity->size() != dim)
    throw SceneError(scene.source + ": dynamics.initial_velocity: expected " + std::to_string(dim) +
                     " components");

  std::unique_ptr<Model> model = build_static_model(setup, 1.0);
  const bool rayleigh = spec.rayleigh_alpha > 0.0 || spec.rayleigh_beta > 0.0;
  const DynamicTerms terms =
      add_dynamics_terms(*model, setup.mesh, DynamicsSetup{spec.lumping, std::nullopt, rayleigh});
  Vector p(model->parameter_layout().size());
  p.head(2 * m) = setup.parameters();
  p.segment(terms.density_offset, m) = setup.density;
  if (rayleigh) p[terms.alpha_offset] = spec.rayleigh_alpha, p[terms.beta_offset] = spec.rayleigh_beta;

  TimeIntegratorOptions options;
  options.scheme = spec.scheme;
  options.time_step = spec.time_step;
  options.newton.max_iterations = std::max(setup.solver.newton.max_iterations, 1);
  options.newton.hessian = setup.solver.newton.hessian;
  TimeIntegrator integrator(*model, options);
  const Vector rest = setup.rest_state();
  Vector v0 = Vector::Zero(rest.size());
  if (spec.initial_velocity)
    for (int v = 0; v < setup.mesh.num_vertices(); ++v) v0.segment(dim * v, dim) = *spec.initial_velocity;
  // Start from rest positions with the prescribed values on the fixed DOFs.
  DynamicState state =
      integrator.initial_state(model->elimination().expand(model->elimination().restrict_state(rest)), v0, p);
  const double setup_seconds = seconds_since(t_start);
  if (log)
    *log << "dynamic scene '" << scene.name << "': " << setup.mesh.num_elements() << " elements, "
         << model->elimination().num_free() << " free DOFs; " << to_string(spec.scheme)
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
  report["tailor_version"] = version_string;
  report["report_format"] = kReportFormatVersion;
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
