// Projected gradient descent, z <- P(z - a g), with a halving (Armijo) line search.
//
// The reference back-end: slow, but with no hidden state, so it shows what the functional
// does. General constraints are not supported (only the box, through the projection).
#include <cmath>
#include <cstdio>
#include <string>

#include "optimizers/backend_detail.hpp"
#include "optimizers/backend_registry.hpp"
#include "forward/core/format_number.hpp"

namespace tailor::detail {

namespace {

constexpr int kMaxHalvings = 50;
// Sufficient decrease along the projected step d = P(z - a g) - z: f(z + d) <= f(z) + c g.d.
// c = 1/2 rather than the usual 1e-4: with halving from a doubled previous step, a small c
// lets the search settle just below 2/L on stiff directions, where each step barely
// contracts (the iterate zig-zags across the valley); c = 1/2 accepts only a <= 1/L there.
constexpr double kArmijo = 0.5;

// The first trial step moves the steepest component across the box's largest finite extent
// (or by 1 when unbounded); later steps start from the last accepted one, doubled, so a good
// step length is found again with one or two halvings.
double initial_step(const Tracker& tracker, const Vector& gradient) {
  double extent = 0.0;
  for (int i = 0; i < tracker.size(); ++i) {
    const double width = tracker.upper()[i] - tracker.lower()[i];
    if (std::isfinite(width)) extent = std::max(extent, width);
  }
  if (extent <= 0.0) extent = 1.0;
  const double g = gradient.lpNorm<Eigen::Infinity>();
  return g > 0.0 ? extent / g : 1.0;
}

}  // namespace

BackendOutcome run_gradient_descent(Tracker& tracker, const Vector& z0) {
  if (!tracker.constraints().empty())
    return {OptimizerStatus::failed, "gradient_descent supports bounds only, not general constraints",
            std::nullopt};
  const OptimizerOptions& options = tracker.options();

  Vector z = z0, g;
  double f = tracker.value_and_gradient(z, g);
  if (!std::isfinite(f))
    return {OptimizerStatus::failed, "the objective cannot be evaluated at the starting point", std::nullopt};
  tracker.record_iteration(z, f);  // resuming: the checkpoint's row, not written again
  // The last accepted step, doubled before the next trial; resuming, the checkpoint's.
  double step = tracker.resumed_state("step").value_or(initial_step(tracker, g) / 2.0);

  for (int iteration = tracker.iterations() + 1; iteration <= options.max_iterations; ++iteration) {
    const double gradient_norm = tracker.projected_gradient_norm(z, g);
    if (gradient_norm <= options.gradient_tolerance)
      return {OptimizerStatus::converged,
              "projected gradient norm " + format_scientific(gradient_norm) + " <= gradient_tolerance", z};
    if (tracker.stop_requested()) return {OptimizerStatus::failed, "", z};

    step *= 2.0;
    bool accepted = false;
    Vector trial, g_trial;
    double f_trial = 0.0;
    for (int halving = 0; halving <= kMaxHalvings; ++halving, step /= 2.0) {
      trial = tracker.project(z - step * g);
      const Vector d = trial - z;
      if (d.lpNorm<Eigen::Infinity>() == 0.0) break;  // the step vanished in round-off
      f_trial = tracker.value(trial);                 // value only: rejected trials need no adjoint solve
      if (tracker.stop_requested()) return {OptimizerStatus::failed, "", z};
      // Strict decrease as well: near round-off the Armijo test accepts equal values and the
      // iterate would wander at the minimum instead of stopping.
      if (!(f_trial < f && f_trial <= f + kArmijo * g.dot(d))) continue;
      // The gradient at the accepted point. Where it cannot be evaluated (the adjoint solve
      // failed), the point counts as a failed trial like one whose forward solve failed.
      f_trial = tracker.value_and_gradient(trial, g_trial);
      if (tracker.stop_requested()) return {OptimizerStatus::failed, "", z};
      if (std::isfinite(f_trial)) {
        accepted = true;
        break;
      }
    }
    if (!accepted)
      return {OptimizerStatus::failed,
              "line search stalled (no sufficient decrease after " + std::to_string(kMaxHalvings) +
                  " halvings; projected gradient norm " + format_scientific(gradient_norm) + ")",
              z};

    z = std::move(trial);
    g = std::move(g_trial);
    f = f_trial;
    tracker.set_backend_state("step", step);
    tracker.record_iteration(z, f);
    tracker.apply_change_tests();
    if (tracker.stop_requested()) return {OptimizerStatus::failed, "", z};
  }
  const double gradient_norm = tracker.projected_gradient_norm(z, g);
  if (gradient_norm <= options.gradient_tolerance)
    return {OptimizerStatus::converged,
            "projected gradient norm " + format_scientific(gradient_norm) + " <= gradient_tolerance", z};
  return {OptimizerStatus::max_iterations,
          "reached max_iterations = " + std::to_string(options.max_iterations), z};
}

}  // namespace tailor::detail

namespace tailor {

// The registry's entries (optimizers/backend_registry.hpp).
BackendEntry gradient_descent_backend_entry() {
  return {"gradient_descent",
          "projected gradient descent with a halving line search, bounds",
          {.bounds = true},
          &detail::run_gradient_descent};
}

}  // namespace tailor
