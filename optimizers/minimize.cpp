// minimize(): validation of the input, dispatch to a back-end through a Tracker
// (optimizers/tracker.hpp), and the result from the Tracker's record.
#include <limits>
#include <stdexcept>

#include "optimizers/backend_detail.hpp"
#include "optimizers/backend_registry.hpp"
#include "optimizers/checkpoint.hpp"
#include "optimizers/interrupt.hpp"
#include "optimizers/optimizer.hpp"

namespace tailor {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Why a checkpoint cannot continue this run; empty when it can.
std::string invalid_checkpoint(const OptimizerCheckpoint& c, int n, OptimizerBackend backend) {
  if (c.backend != backend)
    return "the checkpoint is of back-end " + to_string(c.backend) + ", not " + to_string(backend);
  if (c.z.size() != n || (c.best_z.size() != 0 && c.best_z.size() != n))
    return "the checkpoint's design has size " + std::to_string(c.z.size()) + ", the functional " +
           std::to_string(n);
  if (!c.z.allFinite()) return "the checkpoint's design is not finite";
  if (c.history.empty() || c.history.back().iteration != c.iteration)
    return "the checkpoint's history does not end at its iteration " + std::to_string(c.iteration);
  return "";
}

}  // namespace

OptimizerResult minimize(ReducedFunctional& functional, const Vector& z0, const Bounds& bounds,
                         const std::vector<Constraint>& constraints, const OptimizerOptions& options,
                         const OptimizerCheckpoint* resume) {
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
  if (invalid.empty() && resume) invalid = invalid_checkpoint(*resume, n, options.backend);
  if (!invalid.empty()) {
    result.message = name + ": " + invalid;
    return result;
  }

  detail::Tracker tracker(functional, bounds, constraints, options, resume);
  // Every back-end wants a feasible start with respect to the box (NLopt rejects others).
  const Vector start = tracker.project(resume ? resume->z : z0);

  detail::BackendOutcome outcome;
  try {
    if (resume && resume->iteration >= options.max_iterations) {
      outcome = {OptimizerStatus::max_iterations,
                 "the checkpoint is at iteration " + std::to_string(resume->iteration) +
                     ", max_iterations = " + std::to_string(options.max_iterations),
                 std::nullopt};
    } else {
      outcome = find_backend(options.backend).run(tracker, start);
    }
  } catch (const std::exception& e) {
    outcome = {OptimizerStatus::failed, std::string("exception: ") + e.what(), std::nullopt};
  } catch (...) {
    outcome = {OptimizerStatus::failed, "unknown exception", std::nullopt};
  }
  tracker.final_checkpoint();

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
  result.counters = tracker.counters();
  result.resumed_from = tracker.resumed_from();
  return result;
}

}  // namespace tailor
