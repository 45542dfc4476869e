#pragma once
// One interface over every optimizer back-end:
//   OptimizerResult r = minimize(functional, z0, bounds, constraints, options);
// Options are plain structs with documented defaults; the result is a status with a reason,
// the final (best) point, and the per-iteration history (Ceres-style summary in report()).
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "adjoint/reduced_functional.hpp"

namespace tailor {

// An optimizer back-end by its registered name (optimizers/backend_registry.hpp, which also
// says what each accepts: bounds, constraints, an exact Hessian). The constants name tailor's
// back-ends; the name is not owned: give a string literal, or a run-time name through
// parse_optimizer_backend, which checks it and views the registry's copy.
class OptimizerBackend {
 public:
  constexpr OptimizerBackend() = default;  // nlopt_lbfgs
  constexpr explicit OptimizerBackend(std::string_view name) : name_(name) {}
  constexpr std::string_view name() const { return name_; }
  friend constexpr bool operator==(OptimizerBackend a, OptimizerBackend b) { return a.name_ == b.name_; }

  static const OptimizerBackend ipopt;                // interior point; bounds + general constraints
  static const OptimizerBackend nlopt_lbfgs;          // NLopt LD_LBFGS (bounds)
  static const OptimizerBackend nlopt_mma;            // NLopt LD_MMA (bounds, inequality constraints)
  static const OptimizerBackend nlopt_slsqp;          // NLopt LD_SLSQP (bounds, all constraints)
  static const OptimizerBackend ceres_lbfgs;          // Ceres GradientProblemSolver, L-BFGS (no bounds)
  static const OptimizerBackend ceres_least_squares;  // Ceres Levenberg-Marquardt, residual form (bounds)
  static const OptimizerBackend gradient_descent;     // projected descent, halving line search (bounds)
  static const OptimizerBackend newton_cg;            // trust-region Newton-CG, curvature products (bounds)

 private:
  std::string_view name_ = "nlopt_lbfgs";
};
inline constexpr OptimizerBackend OptimizerBackend::ipopt{"ipopt"};
inline constexpr OptimizerBackend OptimizerBackend::nlopt_lbfgs{"nlopt_lbfgs"};
inline constexpr OptimizerBackend OptimizerBackend::nlopt_mma{"nlopt_mma"};
inline constexpr OptimizerBackend OptimizerBackend::nlopt_slsqp{"nlopt_slsqp"};
inline constexpr OptimizerBackend OptimizerBackend::ceres_lbfgs{"ceres_lbfgs"};
inline constexpr OptimizerBackend OptimizerBackend::ceres_least_squares{"ceres_least_squares"};
inline constexpr OptimizerBackend OptimizerBackend::gradient_descent{"gradient_descent"};
inline constexpr OptimizerBackend OptimizerBackend::newton_cg{"newton_cg"};

std::string to_string(OptimizerBackend backend);
// A registered back-end's kind; std::invalid_argument naming the registered ones otherwise.
OptimizerBackend parse_optimizer_backend(const std::string& name);
std::ostream& operator<<(std::ostream& out, OptimizerBackend backend);

// Box bounds; empty vectors mean unbounded. Use +-infinity for one-sided bounds.
struct Bounds {
  Vector lower, upper;
};

// c(z) <= 0 (inequality) or c(z) = 0 (equality); evaluate fills the gradient when non-null.
struct Constraint {
  std::string name;
  bool equality = false;
  std::function<double(const Vector& z, Vector* gradient)> evaluate;
};

struct OptimizerCheckpoint;  // optimizers/checkpoint.hpp

// The curvature newton_cg's CG steps use (optimizers/newton_cg_backend.cpp).
//  automatic     the functional's Gauss-Newton products where it has them (a least-squares
//                objective), else its exact Hessian-vector products, else forward differences
//                of its gradient (each product then costs a forward and an adjoint solve; the
//                result's message says so);
//  exact         Hessian-vector products only (newton_cg refuses a functional without them);
//  gauss_newton  Gauss-Newton products only (no third derivatives; positive semidefinite;
//                newton_cg refuses a functional without them).
enum class CurvatureProducts { automatic, exact, gauss_newton };
std::string to_string(CurvatureProducts curvature);

struct OptimizerOptions {
  OptimizerBackend backend = OptimizerBackend::nlopt_lbfgs;
  int max_iterations = 200;
  // Stop when the (projected) gradient's infinity norm is below this (absolute).
  double gradient_tolerance = 1e-8;
  // Stop when the objective changes by less than this (absolute) between iterations.
  double objective_tolerance = 0.0;
  // Stop when the step's infinity norm is below this (absolute); 0 = off.
  double step_tolerance = 0.0;
  double time_limit_seconds = 0.0;  // 0 = none
  // Ipopt only: use Hessian-vector products to assemble the exact Hessian (small problems),
  // otherwise limited-memory BFGS.
  bool exact_hessian = false;
  // newton_cg only: see CurvatureProducts.
  CurvatureProducts curvature = CurvatureProducts::automatic;
  // newton_cg only: precondition its CG with the functional's Gauss-Newton diagonal where it
  // offers one (ReducedFunctional::gauss_newton_diagonal). Off: measured to cost more products.
  bool precondition_curvature = false;
  // newton_cg with Gauss-Newton products only: its CG also stops once the model's last decrease
  // is within this fraction of the objective the step predicts (the objective resolved to this
  // relative accuracy; see CgStop in optimizers/newton_cg_backend.cpp); 0 = only the residual
  // test. Measured on recovery_bench: 20-30% fewer products to the bench's target.
  double cg_objective_resolution = 1e-4;
  std::ostream* progress = nullptr;  // one line per iteration when set
  // Checkpoints (optimizers/checkpoint.hpp): when on_checkpoint is set, it is called with the
  // run's state after every checkpoint_every-th iteration (0 = never) and once at the end of
  // the run, so that minimize(..., &checkpoint) can continue from it. An exception from it
  // stops the run (status failed, with its message).
  int checkpoint_every = 10;
  std::function<void(const OptimizerCheckpoint&)> on_checkpoint;
};

enum class OptimizerStatus { converged, max_iterations, time_limit, interrupted, failed };
std::string to_string(OptimizerStatus status);

struct OptimizerIteration {
  int iteration = 0;
  double objective = 0.0;
  double gradient_norm = 0.0;  // infinity norm of the (projected) gradient
  double step_norm = 0.0;      // infinity norm of z_k - z_{k-1}
  double seconds = 0.0;        // cumulative wall time
  int forward_solves = 0;      // cumulative
  int adjoint_solves = 0;      // cumulative
};

struct OptimizerResult {
  OptimizerStatus status = OptimizerStatus::failed;
  std::string message;  // readable reason, including the back-end's own status
  Vector z;             // best point found
  double objective = 0.0;
  std::vector<OptimizerIteration> history;
  int evaluations = 0;
  // Evaluations that failed (the forward solve did not converge at a trial point, or the value
  // was not finite): treated as infinitely bad points, so the back-end shortened its step.
  int failed_evaluations = 0;
  double seconds = 0.0;  // of the whole run, including the part before a resume
  // Work of the functional during the run (solves and their seconds), including the part
  // before a resume.
  FunctionalCounters counters;
  // When the run continued from a checkpoint: its iteration (history rows up to it come from
  // the checkpoint).
  std::optional<int> resumed_from;
  bool converged() const { return status == OptimizerStatus::converged; }
  std::string report() const;
};

// Runs the chosen back-end. Never throws for numerical trouble: a failing back-end returns
// status failed with its message and the best point seen. SIGINT (Ctrl-C) during the run and
// the time limit stop it cleanly with the best point so far.
//
// With `resume`, the run continues from that checkpoint (of the same back-end and design size)
// instead of z0: the history, counts and time go on from it, and the back-end starts at the
// checkpoint's iterate with what of its state it can take back (optimizers/checkpoint.hpp).
OptimizerResult minimize(ReducedFunctional& functional, const Vector& z0, const Bounds& bounds,
                         const std::vector<Constraint>& constraints, const OptimizerOptions& options,
                         const OptimizerCheckpoint* resume = nullptr);

}  // namespace tailor
