#include "problems/report_header.hpp"

#include "forward/solve/threads.hpp"
#include "tailor_version.hpp"

namespace tailor {

void add_report_header(nlohmann::ordered_json& report) {
  report["tailor_version"] = version_string;
  report["report_format"] = kReportFormatVersion;
  const ThreadReport threads = current_threads();
  report["threads"] = {{"assembly", threads.assembly},
                       {"blas", threads.blas},
                       {"factorization", threads.factorization},
                       {"blas_library", threads.blas_library},
                       {"blas_core", threads.blas_core}};
}

nlohmann::ordered_json linear_solver_json(const LinearSolver* solver) {
  if (!solver) return {{"name", "cholmod"}};
  const LinearSolverInfo i = solver->info();
  const auto optional_text = [](const std::string& text) {
    return text.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(text);
  };
  nlohmann::ordered_json last = {{"converged", i.last.converged},
                                 {"iterations", i.last.iterations},
                                 {"relative_residual", i.last.relative_residual},
                                 {"relative_tolerance", i.last.relative_tolerance}};
  if (!i.last.message.empty()) last["message"] = i.last.message;
  return {{"name", i.name},
          {"options", i.options},
          {"options_in_effect", optional_text(i.options_in_effect)},
          {"krylov_method", optional_text(i.krylov_method)},
          {"preconditioner", optional_text(i.preconditioner)},
          {"factorization_package", optional_text(i.factorization_package)},
          {"near_null_space", i.near_null_space},
          {"relative_tolerance", i.relative_tolerance},
          {"absolute_tolerance", i.absolute_tolerance},
          {"divergence_tolerance", i.divergence_tolerance},
          {"max_iterations", i.max_iterations},
          {"processes", i.processes},
          {"assembly", i.assembles_by_parts ? "by_parts" : "replicated"},
          {"solves", i.solves},
          {"iterations", i.iterations},
          {"recent_iterations", i.recent_iterations},
          {"last_solve", i.solves > 0 ? last : nlohmann::ordered_json(nullptr)}};
}

nlohmann::ordered_json to_json(const Eigen::VectorXd& v) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (Eigen::Index k = 0; k < v.size(); ++k) out.push_back(v[k]);
  return out;
}

nlohmann::json matrix_json(const Eigen::MatrixXd& M) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < M.rows(); ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index j = 0; j < M.cols(); ++j) row.push_back(M(i, j));
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace tailor
