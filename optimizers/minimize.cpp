// minimize(): validation of the input, dispatch to a back-end through a Tracker
// (optimizers/tracker.hpp), and the result from the Tracker's record.
#include <limits>
#include <stdexcept>

#include "optimizers/backend_detail.hpp"
#include "optimizers/interrupt.hpp"
#include "optimizers/optimizer.hpp"

namespace tailor {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

OptimizerResult minimize(ReducedFunctional& functional, const Vector& z0, const Bounds& bounds,
                         const std::vector<Constraint>& constraints, const OptimizerOptions& options) {
  detail::SigintGuard sigint_guard;
  const std::string name = to_string(options.backend);
  OptimizerResult result;
  result.z = z0;
  result.objective = kInf;

  // Input errors are reported like any other failure: minimize() does not throw.
  const int n = functional.size();
  std::string invalid;
  if (z0.size() != n) {
    invalid =
        "starting point has size " + std::to_string(z0.size()) + ", the functional " + std::to_string(n);
  } else if ((bounds.lower.size() != 0 && bounds.lower.size() != n) ||
             (bounds.upper.size() != 0 && bounds.upper.size() != n)) {
    invalid = "bounds must be empty or of size " + std::to_string(n);
  } else if (bounds.lower.size() == n && bounds.upper.size() == n &&
             (bounds.lower.array() > bounds.upper.array()).any()) {
    invalid = "a lower bound exceeds its upper bound";
  } else if (!z0.allFinite()) {
    invalid = "starting point is not finite";
  }
  for (const auto& constraint : constraints)
    if (!constraint.evaluate) invalid = "constraint '" + constraint.name + "' has no evaluate";
  if (!invalid.empty()) {
    result.message = name + ": " + invalid;
    return result;
  }

  detail::Tracker tracker(functional, bounds, constraints, options);
  // Every back-end wants a feasible start with respect to the box (NLopt rejects others).
  const Vector start = tracker.project(z0);

  detail::BackendOutcome outcome;
  try {
    switch (options.backend) {
      case OptimizerBackend::ipopt:
        outcome = detail::run_ipopt(tracker, start);
        break;
      case OptimizerBackend::nlopt_lbfgs:
      case OptimizerBackend::nlopt_mma:
      case OptimizerBackend::nlopt_slsqp:
        outcome = detail::run_nlopt(tracker, start);
        break;
      case OptimizerBackend::ceres_lbfgs:
        outcome = detail::run_ceres_lbfgs(tracker, start);
        break;
      case OptimizerBackend::ceres_least_squares:
        outcome = detail::run_ceres_least_squares(tracker, start);
        break;
      case OptimizerBackend::gradient_descent:
        outcome = detail::run_gradient_descent(tracker, start);
        break;
    }
  } catch (const std::exception& e) {
    outcome = {OptimizerStatus::failed, std::string("exception: ") + e.what(), std::nullopt};
  } catch (...) {
    outcome = {OptimizerStatus::failed, "unknown exception", std::nullopt};
  }

  // A stop from outside the back-end (SIGINT, time limit, our own convergence or iteration
  // test, an error inside a callback) explains the back-end's status, so it takes precedence.
  if (tracker.stop_status()) {
    outcome.status = *tracker.stop_status();
    outcome.message = tracker.stop_message() + (outcome.message.empty() ? "" : " [" + outcome.message + "]");
  }
  // Whatever the back-end concluded, a run without a single successful evaluation has
  // found nothing.
  if (!tracker.has_best() && outcome.status != OptimizerStatus::failed &&
      outcome.status != OptimizerStatus::interrupted && outcome.status != OptimizerStatus::time_limit) {
    outcome.message = "no point could be evaluated [" + outcome.message + "]";
    outcome.status = OptimizerStatus::failed;
  }
  result.status = outcome.status;
  result.message = name + ": " + outcome.message;

  const bool normal_end = !tracker.stop_status() && (outcome.status == OptimizerStatus::converged ||
                                                     outcome.status == OptimizerStatus::max_iterations);
  if (!constraints.empty() && normal_end && outcome.final_point && outcome.final_point->size() == n) {
    result.z = *outcome.final_point;
    const auto known = tracker.known_value(result.z);
    result.objective = known ? *known : tracker.value(result.z);
  } else if (tracker.has_best()) {
    result.z = tracker.best_point();
    result.objective = tracker.best_objective();
  } else {
    result.z = start;
  }
  result.history = tracker.history();
  result.evaluations = tracker.evaluations();
  result.failed_evaluations = tracker.failed_evaluations();
  result.seconds = tracker.seconds();
  return result;
}

}  // namespace tailor
