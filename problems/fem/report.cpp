#include "problems/fem/report.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "forward/mesh/mesh_io.hpp"
#include "problems/json_text.hpp"
#include "problems/report_file.hpp"
#include "problems/report_header.hpp"

namespace tailor {
namespace {

using Json = nlohmann::ordered_json;  // keeps the documented key order in the file

// Residuals (or energies) of every iterate of a Newton solve, including the last one.
template <class Get, class Final>
void append_history(const NewtonResult& r, Json& out, Get get, Final final_value) {
  for (const NewtonIteration& it : r.history) out.push_back(get(it));
  // The last iterate has no history entry unless the solve stopped inside that iteration
  // (a failed line search records the attempted iteration).
  if (r.history.empty() || r.history.back().iteration < r.iterations) out.push_back(final_value);
}

}  // namespace

void write_report_json(const std::string& path, const Scene& scene, const StaticSetup& setup,
                       const StaticSolution& solution, const RunTimings& timings) {
  Json report;
  add_report_header(report);
  report["scene"] = {{"name", scene.name}, {"source", scene.source}};
  report["status"] = solution.status;
  report["message"] = solution.message;
  report["converged"] = solution.converged;
  report["residual"] = solution.residual;

  int iterations = 0;
  Json steps = Json::array(), residuals = Json::array(), energies = Json::array();
  for (const LoadStep& step : solution.steps) {
    const NewtonResult& r = step.newton;
    iterations += r.iterations;
    steps.push_back({{"load_factor", step.load_factor},
                     {"status", to_string(r.status)},
                     {"message", r.message},
                     {"iterations", r.iterations},
                     {"initial_residual", r.initial_residual},
                     {"final_residual", r.final_residual},
                     {"residual_floor", r.residual_floor},
                     {"floor_ratio", r.floor_ratio},
                     {"accuracy", r.accuracy},
                     {"solution_change", r.solution_change},
                     {"condition_estimate",
                      std::isfinite(r.condition_estimate) ? Json(r.condition_estimate) : Json(nullptr)},
                     {"energy", r.final_energy},
                     {"seconds", r.total_seconds}});
    append_history(
        r, residuals, [](const NewtonIteration& it) { return it.residual; }, r.final_residual);
    append_history(
        r, energies, [](const NewtonIteration& it) { return it.energy; }, r.final_energy);
  }
  report["iterations"] = iterations;
  report["linear_solver"] = linear_solver_json(setup.solver.newton.linear_solver.get());
  report["load_steps"] = steps;
  report["residual_history"] = residuals;
  report["energy_history"] = energies;
  report["timings"] = {{"total", timings.total},
                       {"setup", timings.setup},
                       {"analysis", timings.analysis},
                       {"assembly", timings.assembly},
                       {"factorization", timings.factorization},
                       {"solve", timings.solve},
                       {"line_search", timings.line_search},
                       {"output", timings.output}};
  report["mesh"] = {{"dim", setup.dim()},
                    {"vertices", setup.mesh.num_vertices()},
                    {"elements", setup.mesh.num_elements()},
                    {"order", setup.order()},
                    {"nodes", setup.num_nodes()}};
  report["dofs"] = {{"total", setup.num_dofs()},
                    {"free", solution.num_free},
                    {"fixed", static_cast<int>(setup.fixed_dofs.size())}};
  // The load actually applied: the last attempted step's share of the full load.
  const double load_factor = solution.steps.empty() ? 1.0 : solution.steps.back().load_factor;
  const Eigen::VectorXd applied =
      load_factor * setup.nodal_forces.reshaped(setup.dim(), setup.num_nodes()).rowwise().sum();
  report["results"] = {{"max_displacement", solution.max_displacement},
                       {"max_displacement_vertex", solution.max_displacement_vertex},
                       {"energy", solution.energy},
                       {"reaction_force_total", to_json(solution.reaction_force_total)},
                       {"applied_force_total", to_json(applied)}};

  write_report_file(path, report);
}

void write_result_vtu(const std::string& path, const StaticSetup& setup, const StaticSolution& solution,
                      const VtkFields& extra) {
  const Mesh& mesh = setup.mesh;
  VtkFields fields = extra;
  fields.point["displacement"] = solution.displacement;
  fields.cell["youngs_modulus"] = setup.youngs_modulus;
  fields.cell["poisson_ratio"] = setup.poisson_ratio;
  fields.cell["density"] = setup.density;
  fields.cell["stress"] = solution.stresses;
  // write_vtu adds the "region" cell field itself, from mesh.element_regions.
  fields.cell["material"] = setup.element_material.cast<double>();
  const Eigen::MatrixXd positions = mesh.rest_positions + solution.displacement;
  write_vtu(path, mesh, fields, &positions);
}

}  // namespace tailor
