#include "problems/material_fit/material_fit_report.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "problems/fem/report.hpp"
#include "problems/fem/spline_curves_json.hpp"
#include "problems/optimizer_report.hpp"
#include "problems/report_file.hpp"

namespace tailor {

std::string force_plot_name(const LoadCase& load_case) { return "force_" + load_case.name + ".png"; }

void write_material_fit_report(const std::string& path, const MaterialFitSpec& spec,
                               const MaterialFitRun& run, const PrincipalStretchCurves& fitted,
                               const Mesh& specimen) {
  using Json = nlohmann::ordered_json;  // keeps the documented key order in the file
  const OptimizerResult& result = run.result;
  Json report;
  add_report_header(report);
  report["kind"] = "material_fit";
  report["scene"] = {{"name", spec.name}, {"source", spec.source}};
  report["status"] = to_string(result.status);
  report["message"] = result.message;
  report["converged"] = result.converged();
  report["backend"] = to_string(spec.optimizer.backend);
  report["iterations"] = result.history.empty() ? 0 : result.history.back().iteration;
  report["evaluations"] = run.evaluations;
  report["history"] = optimizer_history_json(result);
  report["objective"] = {
      {"initial", result.history.empty() ? Json(nullptr) : Json(result.history.front().objective)},
      {"final", result.objective}};
  report["solves"] = {{"forward", run.forward_solves}, {"adjoint", run.adjoint_solves}};

  report["relative_force_error"] = run.relative_force_error;
  report["initial_relative_force_error"] = run.initial_relative_force_error;
  report["relative_stress_error"] =
      run.relative_stress_error ? Json(*run.relative_stress_error) : Json(nullptr);
  Json cases = Json::array();
  for (std::size_t c = 0; c < spec.cases.size(); ++c) {
    const LoadCase& lc = spec.cases[c];
    cases.push_back({{"name", lc.name},
                     {"kind", to_string(lc.kind)},
                     {"amplitudes", lc.amplitudes},
                     {"target", run.target[c]},
                     {"initial", run.initial[c]},
                     {"fitted", run.fitted[c]},
                     {"plot", force_plot_name(lc)}});
  }
  report["load_cases"] = cases;
  Json constraints = Json::array();
  for (const ShapeConstraint& shape : spec.shapes)
    constraints.push_back(
        {{"curve", shape.curve},
         {"kind", to_string(shape.shape)},
         {"range", std::isfinite(shape.lower) || std::isfinite(shape.upper)
                       ? Json::array({std::isfinite(shape.lower) ? Json(shape.lower) : Json(nullptr),
                                      std::isfinite(shape.upper) ? Json(shape.upper) : Json(nullptr)})
                       : Json(nullptr)},
         {"count", shape_constraints(fitted, {shape}).size()}});
  report["constraints"] = constraints;
  report["curves"] = principal_stretch_curves_json(fitted);
  report["material_file"] = "material.json";

  const MaterialFitTimings& t = run.timings;
  report["timings"] = {{"total", t.total},     {"setup", t.setup},     {"optimization", t.optimization},
                       {"forward", t.forward}, {"adjoint", t.adjoint}, {"output", t.output}};
  report["mesh"] = {
      {"dim", specimen.dim()}, {"vertices", specimen.num_vertices()}, {"elements", specimen.num_elements()}};

  write_report_file(path, report);
}

}  // namespace tailor
