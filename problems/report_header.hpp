#pragma once
// The fields every report.json starts with: the tailor version, the report layout's version
// (kReportFormatVersion) and the thread configuration the run used (OpenMP, BLAS and CHOLMOD's
// factorization; see forward/solve/threads.hpp), so that timings in a report can be read.
#include <nlohmann/json.hpp>

#include "forward/solve/linear_solver.hpp"

namespace tailor {

// Version of the report layout; bumped only when a field changes meaning or is removed.
inline constexpr int kReportFormatVersion = 1;

// report["tailor_version"], report["report_format"], report["threads"] = {assembly, blas,
// factorization, blas_library, blas_core}.
void add_report_header(nlohmann::ordered_json& report);

// report["linear_solver"]: {"name": "cholmod"} for the default (no LinearSolver), else the
// solver's LinearSolverInfo (docs/petsc.md lists the fields).
nlohmann::ordered_json linear_solver_json(const LinearSolver* solver);

// A vector as a JSON array of its entries (every report's vectors).
nlohmann::ordered_json to_json(const Eigen::VectorXd& v);

// A matrix as a JSON array of its rows (effective tensors in the homogenization reports).
nlohmann::json matrix_json(const Eigen::MatrixXd& M);

}  // namespace tailor
