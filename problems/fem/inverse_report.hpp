#pragma once
// Outputs of the inverse verbs: what `tailor gradcheck` and `tailor run` found, and the files
// they write: DIR/gradcheck.json, and DIR/report.json (inverse layout, documented field by
// field in docs/scenes.md) with DIR/result.vtu.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "adjoint/taylor_test.hpp"
#include "optimizers/optimizer.hpp"
#include "problems/fem/inverse_handles.hpp"
#include "problems/fem/inverse_problem.hpp"

namespace tailor {

// The transient adjoint's backward solves with NewtonOptions::linear_solver (the last
// backward pass of a dynamic gradcheck on it).
struct AdjointLinearSolves {
  double relative_tolerance = 0.0;  // TransientFunctionalOptions::linear_relative_tolerance
  int solves = 0;
  long long iterations = 0;
  double last_relative_residual = 0.0;
};

struct GradcheckRun {
  std::string scene_name, scene_source;
  int design_size = 0;
  unsigned seed = 1;
  TaylorTestResult gradient;                                 // taylor_test at z0
  std::optional<TaylorTestResult> hessian;                   // taylor_test_hessian, when asked for
  std::string report_path;                                   // out_dir/gradcheck.json
  LinearSolverPtr linear_solver;                             // the functional's (empty: CHOLMOD)
  std::optional<AdjointLinearSolves> adjoint_linear_solves;  // dynamic scenes on linear_solver
  bool passed() const { return gradient.passed() && (!hessian || hessian->passed()); }
};

// Wall-clock seconds of the parts of an inverse run.
struct InverseTimings {
  double total = 0.0;         // up to (not including) writing report.json
  double setup = 0.0;         // scene, model, objective (including synthetic forward solves)
  double optimization = 0.0;  // minimize()
  double forward = 0.0;       // Newton solves inside the functional
  double adjoint = 0.0;       // adjoint solves inside the functional
  double output = 0.0;        // the final equilibrium and result.vtu
  double modes = 0.0;         // material modes (granularity modes; part of setup)
};

// A run that continued from a checkpoint (tailor run --resume).
struct ResumedRun {
  std::string checkpoint;  // the file it was read from
  int iteration = 0;       // the checkpoint's iteration; the history's rows up to it come from it
};

struct InverseRun {
  std::unique_ptr<InverseProblem> problem;
  OptimizerResult result;           // result.z: the best design found
  Eigen::VectorXd design_values;    // E per design variable at result.z
  Eigen::VectorXd youngs_modulus;   // E per element at result.z
  std::vector<double> term_values;  // coefficient * term at result.z, per objective term
  std::optional<FieldError> error;  // against the ground truth, when known
  std::optional<FieldError> initial_error;
  StaticSolution solution;            // the equilibrium at result.z (with the scene's load steps)
  std::vector<HandleResult> handles;  // per handle at result.z, when the scene has handles and it converged
  InverseTimings timings;
  std::optional<ResumedRun> resumed;
  std::string report_path;      // out_dir/report.json
  std::string result_path;      // out_dir/result.vtu
  std::string checkpoint_path;  // out_dir/checkpoint.json; empty when checkpoints are off
};

// Throw std::runtime_error when a file cannot be written.
void write_gradcheck_json(const std::string& path, const GradcheckRun& run);
void write_inverse_report_json(const std::string& path, const InverseRun& run);
// result.vtu of the static verbs at the best design, plus cell fields "youngs_modulus_initial"
// and, with a ground truth, "youngs_modulus_true" and "youngs_modulus_relative_error" (E/T - 1);
// for a modal design with output_modes = k, "material_mode_1" ... "material_mode_k" (Phi's columns).
void write_inverse_result_vtu(const std::string& path, const InverseRun& run);

}  // namespace tailor
