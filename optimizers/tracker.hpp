#pragma once
// Private to optimizers/: the bookkeeping every back-end shares.
//
// A Tracker wraps the ReducedFunctional for the duration of one minimize() call. Back-ends
// never call the functional directly: they go through the Tracker, which
//  - counts evaluations and serves repeated requests at the same z from a one-point cache
//    (Ipopt and Ceres ask for the value and the gradient of one point in separate calls);
//  - turns EvaluationError into "infinitely bad point" (+inf, or false for residuals) and
//    any other exception into a recorded failure plus a stop request, so that no exception
//    ever crosses a C or C++ solver library;
//  - keeps the best point seen: the lowest objective, and, when there are general
//    constraints, feasible points (violation <= kFeasibilityTolerance) before infeasible
//    ones (otherwise the best point would be an infeasible point below the constrained
//    minimum);
//  - writes one history row per back-end iteration (and prints it when progress is set);
//  - answers stop_requested(): SIGINT, the time limit, or a stop asked for by a back-end;
//  - hands a checkpoint (optimizers/checkpoint.hpp) to OptimizerOptions::on_checkpoint every
//    checkpoint_every rows and at the end, and, resuming, starts from one: the history,
//    counts, best point and clock go on from it, the back-end's own state is offered back
//    through resumed_state(), and the back-end's first row (at the checkpoint's iterate, which
//    the checkpoint already holds) is not written again.
#include <chrono>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "optimizers/checkpoint.hpp"
#include "optimizers/optimizer.hpp"

namespace tailor::detail {

// Violation of a general constraint or bound above which a point counts as infeasible when
// ranking best points. Absolute; constraints are expected to be reasonably scaled.
inline constexpr double kFeasibilityTolerance = 1e-6;

class Tracker {
 public:
  Tracker(ReducedFunctional& functional, const Bounds& bounds, const std::vector<Constraint>& constraints,
          const OptimizerOptions& options, const OptimizerCheckpoint* resume = nullptr);

  ReducedFunctional& functional() { return functional_; }
  int size() const { return n_; }
  const OptimizerOptions& options() const { return options_; }
  const std::vector<Constraint>& constraints() const { return constraints_; }
  // Bounds expanded to size n (+-infinity where absent).
  const Vector& lower() const { return lower_; }
  const Vector& upper() const { return upper_; }
  bool has_finite_bounds() const;
  Vector project(const Vector& z) const;  // onto the box

  // Evaluations; they never throw. value* return +inf where the functional cannot be
  // evaluated (EvaluationError, non-finite result) or failed otherwise (then a stop with
  // status failed is requested as well).
  double value(const Vector& z);
  double value_and_gradient(const Vector& z, Vector& gradient);
  // Residual form: false where it cannot be evaluated. Records 1/2 ||r||^2 as the objective.
  bool residuals(const Vector& z, Vector& r, Matrix* jacobian);
  // Constraint i at z (gradient when non-null); NaN where it cannot be evaluated.
  double constraint(int i, const Vector& z, Vector* gradient);
  // The functional's Hessian-vector product at z (Gauss-Newton product with gauss_newton) into
  // out; false where it cannot be evaluated (EvaluationError, non-finite) or failed otherwise
  // (then a stop with status failed is requested as well).
  bool curvature_product(const Vector& z, const Vector& v, bool gauss_newton, Vector& out);
  // The same by a forward difference of gradients, (g(z + h v) - g) / h with g the gradient at
  // z and h = 1e-6 (1 + |z|_inf) / |v|_inf, for functionals without curvature products: one
  // forward and one adjoint solve at z + h v (not an evaluation of the run: not counted, cached
  // or considered for the best point).
  bool gradient_difference(const Vector& z, const Vector& g, const Vector& v, Vector& out);
  // The functional's estimate of the Gauss-Newton diagonal at z (ReducedFunctional::
  // gauss_newton_diagonal); false where it has none or it cannot be evaluated.
  bool gauss_newton_diagonal(const Vector& z, Vector& out);

  // Infinity norm of z - P(z - g): the gradient with the components that push against an
  // active bound removed (and, near a bound, cut to the distance to it).
  double projected_gradient_norm(const Vector& z, const Vector& gradient) const;
  // The gradient at z if the last gradient evaluation was at z.
  const Vector* cached_gradient(const Vector& z) const;

  // One history row at the iterate z with objective f. The gradient norm comes from the
  // cached gradient at z; fallback_gradient_norm (the back-end's own measure, else NaN) is
  // used where none is cached.
  void record_iteration(const Vector& z, double f,
                        double fallback_gradient_norm = std::numeric_limits<double>::quiet_NaN());
  // Iterations after the starting point (row 0).
  int iterations() const { return history_.empty() ? 0 : static_cast<int>(history_.size()) - 1; }
  const std::vector<OptimizerIteration>& history() const { return history_; }
  // Applies objective_tolerance and step_tolerance to the last two rows and requests a
  // converged stop when either holds; for back-ends without such tests of their own.
  void apply_change_tests();

  // Stop handling. stop_requested() also polls SIGINT and the clock; the first reason wins.
  bool stop_requested();
  void request_stop(OptimizerStatus status, const std::string& message);
  const std::optional<OptimizerStatus>& stop_status() const { return stop_status_; }
  const std::string& stop_message() const { return stop_message_; }

  bool has_best() const { return has_best_; }
  const Vector& best_point() const { return best_z_; }
  double best_objective() const { return best_f_; }
  int best_updates() const { return best_updates_; }  // how often the best point changed
  // Objective at z if evaluated (best point or the cached points).
  std::optional<double> known_value(const Vector& z) const;
  int evaluations() const { return evaluations_; }
  int failed_evaluations() const { return failed_evaluations_; }
  double seconds() const;  // since the start of the run (before a resume too)
  // The functional's work during the run (before a resume too).
  FunctionalCounters counters() const;

  // Checkpoints. A back-end records what of its state a resumed run can take back with
  // set_backend_state() before it records the iteration the state belongs to; resuming, it
  // asks for it with resumed_state().
  bool resumed() const { return resumed_from_.has_value(); }
  std::optional<int> resumed_from() const { return resumed_from_; }
  std::optional<double> resumed_state(const std::string& name) const;
  void set_backend_state(const std::string& name, double value) { backend_state_[name] = value; }
  // The objective of row 0, or `fallback` before there is one (relative tolerances refer to it).
  double first_objective(double fallback) const {
    return history_.empty() ? fallback : history_.front().objective;
  }
  // At the end of the run: a checkpoint of the last row unless it has one already.
  void final_checkpoint();

 private:
  void consider(const Vector& z, double f);
  double violation(const Vector& z);
  void fail(const std::string& what);
  void print_row(const OptimizerIteration& row);
  void checkpoint();

  ReducedFunctional& functional_;
  const std::vector<Constraint>& constraints_;
  const OptimizerOptions& options_;
  int n_;
  Vector lower_, upper_;
  std::chrono::steady_clock::time_point start_;
  FunctionalCounters start_counters_;  // the functional's counters at the start
  // Resuming: the checkpoint's time and work, and its iteration.
  double seconds_offset_ = 0.0;
  FunctionalCounters counters_offset_;
  std::optional<int> resumed_from_;
  bool skip_resumed_row_ = false;
  std::map<std::string, double> resumed_state_;

  int evaluations_ = 0;
  int failed_evaluations_ = 0;
  // One-point caches: last value, last gradient, last residuals.
  std::optional<std::pair<Vector, double>> value_cache_;
  std::optional<Vector> gradient_z_;
  Vector gradient_;
  double gradient_f_ = 0.0;
  std::optional<Vector> residual_z_;
  Vector residual_r_;
  std::optional<Matrix> residual_jacobian_;
  bool residual_ok_ = false;

  bool has_best_ = false;
  Vector best_z_;
  double best_f_ = 0.0;
  double best_violation_ = 0.0;
  int best_updates_ = 0;

  std::vector<OptimizerIteration> history_;
  Vector last_row_z_;
  std::optional<OptimizerStatus> stop_status_;
  std::string stop_message_;

  std::map<std::string, double> backend_state_;
  int last_checkpoint_ = -1;  // iteration of the last checkpoint handed out (or resumed from)
  bool checkpoint_failed_ = false;
};

}  // namespace tailor::detail
