#pragma once
// Private to optimizers/: what every back-end returns, and the back-ends themselves. They
// evaluate the functional only through the Tracker (optimizers/tracker.hpp).
#include <optional>
#include <string>

#include "optimizers/tracker.hpp"

namespace tailor::detail {

// What a back-end reports. minimize() overrides status and message when the Tracker stopped
// the run (SIGINT, time limit, a failure inside a callback).
struct BackendOutcome {
  OptimizerStatus status = OptimizerStatus::failed;
  std::string message;
  // The back-end's own answer. With general constraints it is returned instead of the best
  // point when the back-end finished normally (it is the point whose KKT conditions it
  // checked); without constraints the best point is returned, which is never worse.
  std::optional<Vector> final_point;
};

// The back-ends. Each takes the starting point already projected onto the bounds.
BackendOutcome run_ipopt(Tracker& tracker, const Vector& z0);
BackendOutcome run_nlopt(Tracker& tracker, const Vector& z0);
BackendOutcome run_ceres_lbfgs(Tracker& tracker, const Vector& z0);
BackendOutcome run_ceres_least_squares(Tracker& tracker, const Vector& z0);
BackendOutcome run_gradient_descent(Tracker& tracker, const Vector& z0);
BackendOutcome run_newton_cg(Tracker& tracker, const Vector& z0);

}  // namespace tailor::detail
