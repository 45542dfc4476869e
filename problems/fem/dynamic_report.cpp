#include "problems/fem/dynamic_report.hpp"

#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "forward/mesh/mesh_io.hpp"
#include "problems/json_text.hpp"
#include "problems/report_file.hpp"
#include "problems/report_header.hpp"

namespace tailor {
namespace {

using Json = nlohmann::ordered_json;

Eigen::MatrixXd as_rows(const Vector& x, int dim) {
  return Eigen::Map<const Eigen::MatrixXd>(x.data(), dim, x.size() / dim).transpose();
}

}  // namespace

std::string write_dynamic_frame(const std::filesystem::path& frames_dir, const StaticSetup& setup,
                                const Vector& rest, const DynamicState& s) {
  const int dim = setup.dim();
  std::ostringstream name;
  name << "frame_" << std::setw(5) << std::setfill('0') << s.step << ".vtu";
  VtkFields fields;
  fields.point["displacement"] = as_rows(s.x - rest, dim);
  fields.point["velocity"] = as_rows(s.v, dim);
  fields.cell["youngs_modulus"] = setup.youngs_modulus;
  const Eigen::MatrixXd positions = as_rows(s.x, dim);
  write_vtu((frames_dir / name.str()).string(), setup.mesh, fields, &positions);
  return "frames/" + name.str();
}

void write_dynamic_series(const std::string& path, const DynamicRun& run) {
  std::ostringstream pvd;
  pvd << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n";
  for (const auto& [time, file] : run.frames)
    pvd << "    <DataSet timestep=\"" << std::setprecision(17) << time << "\" file=\"" << file << "\"/>\n";
  pvd << "  </Collection>\n</VTKFile>\n";
  write_text_file_atomically(path, pvd.str());
}

void write_dynamic_report_json(const std::string& path, const Scene& scene, const DynamicRun& run) {
  const DynamicsSpec& spec = *scene.dynamics;
  Json report;
  add_report_header(report);
  report["scene"] = {{"name", scene.name}, {"source", scene.source}};
  report["kind"] = "dynamics";
  report["status"] = run.completed ? "completed" : "failed";
  report["message"] = run.message;
  report["warnings"] = run.warnings;
  report["dynamics"] = {{"scheme", to_string(spec.scheme)},
                        {"time_step", spec.time_step},
                        {"steps", spec.steps},
                        {"steps_done", run.steps_done},
                        {"mass", spec.lumping == MassLumping::lumped ? "lumped" : "consistent"},
                        {"rayleigh_alpha", spec.rayleigh_alpha},
                        {"rayleigh_beta", spec.rayleigh_beta},
                        {"solver", spec.solver_method}};
  Json steps = Json::array();
  double step_seconds = 0.0;
  for (const DynamicStepRecord& r : run.records) {
    step_seconds += r.seconds;
    steps.push_back({{"step", r.step},
                     {"time", r.time},
                     {spec.solver_method == "descent" ? "descent_iterations" : "newton_iterations",
                      r.newton_iterations},
                     {"final_residual", r.residual},
                     {"kinetic_energy", r.kinetic},
                     {"potential_energy", r.potential},
                     {"total_energy", r.kinetic + r.potential},
                     {"seconds", r.seconds}});
  }
  report["steps"] = steps;
  report["timings"] = {{"total", run.timings.total},
                       {"setup", run.timings.setup},
                       {"steps", step_seconds},
                       {"output", run.timings.output}};
  if (run.reduction) {
    const ReducedRunSummary& r = *run.reduction;
    report["reduction"] = {{"basis", r.basis},
                           {"reduced_coordinates", r.r},
                           {"domains", r.domains},
                           {"energy", r.energy},
                           {"rotations", r.rotations},
                           {"rotation_blend", r.rotation_blend},
                           {"polynomial_groups", r.groups},
                           {"largest_group", r.largest_group},
                           {"precomputation_seconds", {{"basis", r.basis_seconds}, {"energy", r.energy_seconds}}}};
  }
  report["series"] = "result.pvd";
  report["linear_solver"] = linear_solver_json(run.linear_solver.get());
  write_report_file(path, report);
}

}  // namespace tailor
