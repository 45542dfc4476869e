#include "problems/fem/inverse_report.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "problems/fem/report.hpp"
#include "problems/json_text.hpp"
#include "problems/optimizer_report.hpp"
#include "problems/report_file.hpp"
#include "problems/report_header.hpp"
#include "problems/taylor_report.hpp"

namespace tailor {
namespace {

using Json = nlohmann::ordered_json;  // keeps the documented key order in the file

// min / max / volume-weighted mean of a per-element field.
Json summary(const Mesh& mesh, const Eigen::VectorXd& field) {
  const Eigen::VectorXd volumes = element_volumes(mesh).cwiseAbs();
  return {{"min", field.minCoeff()}, {"max", field.maxCoeff()}, {"mean", volumes.dot(field) / volumes.sum()}};
}

Json error_json(const FieldError& e) {
  return {{"relative_l2_error", e.relative_l2}, {"max_relative_error", e.max_relative}};
}

// A Taylor test result as JSON: its own layout, parsed back so it can be extended.
Json optional_vector(const Vector& v) { return v.size() > 0 ? to_json(v) : Json(nullptr); }

// The handles term's settings and, per handle, what it achieved (see docs/scenes.md).
Json handles_json(const InverseProblem& problem, const std::vector<HandleResult>& results) {
  const HandlesTerm* term = find_handles_term(problem.spec);
  Json list = Json::array();
  for (const HandleResult& r : results) {
    const bool has_f = r.target_force.size() > 0, has_u = r.target_displacement.size() > 0;
    list.push_back(
        {{"key", r.key},
         {"vertices", r.vertices},
         {"weight", r.weight},
         {"force", to_json(r.total_force)},
         {"target_force", optional_vector(r.target_force)},
         {"force_per_vertex", r.force_per_vertex},
         {"force_error", has_f ? Json(r.force_error) : Json(nullptr)},
         {"relative_force_error", has_f ? Json(r.relative_force_error) : Json(nullptr)},
         {"displacement", to_json(r.displacement)},
         {"target_displacement", optional_vector(r.target_displacement)},
         {"displacement_error", has_u ? Json(r.displacement_error) : Json(nullptr)},
         {"relative_displacement_error", has_u ? Json(r.relative_displacement_error) : Json(nullptr)}});
  }
  return {{"alpha", term ? term->alpha : 1.0},
          {"beta", term ? term->beta : 1.0},
          {"displacement_variables", problem.handles->size()},
          {"list", list}};
}

}  // namespace

void write_gradcheck_json(const std::string& path, const GradcheckRun& run) {
  // The Taylor test's own fields stay at the top level.
  Json document = taylor_json(run.gradient);
  document["passed"] = run.passed();
  document["scene"] = {{"name", run.scene_name}, {"source", run.scene_source}};
  document["design_size"] = run.design_size;
  document["seed"] = run.seed;
  if (run.hessian) document["hessian"] = taylor_json(*run.hessian);
  document["linear_solver"] = linear_solver_json(run.linear_solver.get());
  if (const auto& a = run.adjoint_linear_solves)
    document["adjoint_linear_solves"] = {{"relative_tolerance", a->relative_tolerance},
                                         {"solves", a->solves},
                                         {"iterations", a->iterations},
                                         {"last_relative_residual", a->last_relative_residual}};
  write_report_file(path, document);
}

void write_inverse_report_json(const std::string& path, const InverseRun& run) {
  const InverseProblem& problem = *run.problem;
  const OptimizerResult& result = run.result;
  const Mesh& mesh = problem.setup.mesh;
  Json report;
  add_report_header(report);
  report["kind"] = "inverse";
  report["scene"] = {{"name", problem.scene_name}, {"source", problem.scene_source}};
  report["status"] = to_string(result.status);
  report["message"] = result.message;
  report["converged"] = result.converged();
  report["backend"] = to_string(problem.spec.optimizer.backend);
  report["iterations"] = result.history.empty() ? 0 : result.history.back().iteration;
  report["evaluations"] = result.evaluations;
  report["failed_evaluations"] = result.failed_evaluations;
  report["resumed"] =
      run.resumed ? Json{{"checkpoint", run.resumed->checkpoint}, {"iteration", run.resumed->iteration}}
                  : Json(nullptr);

  report["history"] = optimizer_history_json(result);

  Json terms = Json::array();
  for (std::size_t k = 0; k < problem.terms.size(); ++k) {
    const ObjectiveTermInfo& t = problem.terms[k];
    terms.push_back({{"key", t.key},
                     {"type", t.type},
                     {"weight", t.weight},
                     {"coefficient", t.coefficient},
                     {"value", k < run.term_values.size() ? Json(run.term_values[k]) : Json(nullptr)}});
  }
  report["objective"] = {
      {"initial", result.history.empty() ? Json(nullptr) : Json(result.history.front().objective)},
      {"final", result.objective},
      {"terms", terms}};
  // The optimization's solves, including those before a resume.
  report["solves"] = {{"forward", result.counters.forward_solves},
                      {"adjoint", result.counters.adjoint_solves}};
  report["linear_solver"] = linear_solver_json(problem.setup.solver.newton.linear_solver.get());

  const DesignSpec& d = problem.spec.design;
  Json design = {{"parameter", d.parameter},
                 {"granularity", to_string(d.granularity)},
                 {"map", to_string(d.map)},
                 {"size", problem.num_material_design()},
                 {"min", d.min ? Json(*d.min) : Json(nullptr)},
                 {"max", d.max ? Json(*d.max) : Json(nullptr)},
                 {"initial", summary(mesh, problem.youngs_modulus(problem.z0))},
                 {"final", summary(mesh, run.youngs_modulus)}};
  if (d.granularity == DesignGranularity::modes) {
    design["modes"] = d.modes ? Json(*d.modes) : Json("full");
    design["mode_weighting"] = d.mode_weighting == AdjacencyWeighting::unit ? "unit" : "facet";
    if (problem.modal && problem.modal->eigenvalues.size() > 0)
      design["eigenvalues"] = to_json(problem.modal->eigenvalues);
  }
  if (d.grouped()) {
    design["labels"] = problem.design_labels;
    design["values"] = to_json(run.design_values);
  }
  if (problem.element_map) {  // a program's own map z -> E (InverseExtensions): z itself
    design["granularity"] = "element_map";
    design["map"] = problem.element_map->name();
    design["min"] = nullptr;
    design["max"] = nullptr;
    design["labels"] = problem.design_labels;
    design["values"] = to_json(run.design_values);
  }
  report["design"] = design;
  if (problem.handles) report["handles"] = handles_json(problem, run.handles);
  if (run.error) {
    Json truth = {{"source", problem.truth_key}};
    truth.update(error_json(*run.error));
    if (run.initial_error) truth["initial"] = error_json(*run.initial_error);
    report["ground_truth"] = truth;
  }
  const InverseTimings& t = run.timings;
  report["timings"] = {{"total", t.total},     {"setup", t.setup},     {"optimization", t.optimization},
                       {"forward", t.forward}, {"adjoint", t.adjoint}, {"output", t.output},
                       {"modes", t.modes}};
  // Means over optimizer iterations (at least one), for interactive-rate comparisons.
  const double iterations = std::max(1, result.history.empty() ? 0 : result.history.back().iteration);
  report["timings"]["per_iteration"] = {{"optimization", t.optimization / iterations},
                                        {"forward", t.forward / iterations},
                                        {"adjoint", t.adjoint / iterations}};
  report["mesh"] = {
      {"dim", mesh.dim()}, {"vertices", mesh.num_vertices()}, {"elements", mesh.num_elements()}};
  write_report_file(path, report);
}

void write_inverse_result_vtu(const std::string& path, const InverseRun& run) {
  const InverseProblem& problem = *run.problem;
  const StaticSetup setup = problem.setup_at(run.result.z);
  VtkFields extra;
  if (problem.handles) {  // 1 + the handle's index on handle vertices, 0 elsewhere
    Eigen::MatrixXd handle = Eigen::MatrixXd::Zero(setup.mesh.num_vertices(), 1);
    for (int h = 0; h < problem.handles->objective->num_handles(); ++h)
      for (int v : problem.handles->objective->handle(h).vertices) handle(v, 0) = h + 1;
    extra.point["handle"] = handle;
  }
  extra.cell["youngs_modulus_initial"] = problem.youngs_modulus(problem.z0);
  if (problem.truth.size() > 0) {
    extra.cell["youngs_modulus_true"] = problem.truth;
    extra.cell["youngs_modulus_relative_error"] =
        run.youngs_modulus.cwiseQuotient(problem.truth).array() - 1.0;
  }
  if (problem.modal)
    for (int j = 0; j < std::min<int>(problem.spec.design.output_modes, problem.modal->modes.cols()); ++j)
      extra.cell["material_mode_" + std::to_string(j + 1)] = problem.modal->modes.col(j);
  write_result_vtu(path, setup, run.solution, extra);
}

}  // namespace tailor
