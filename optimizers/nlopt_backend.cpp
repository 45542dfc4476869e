// NLopt back-ends: LD_LBFGS (bounds), LD_MMA (bounds, inequality constraints) and LD_SLSQP
// (bounds, equality and inequality constraints).
//
// NLopt has no iteration callback and counts objective evaluations, not iterations, so:
//  - a history row is written for every evaluation that improves the best point (an accepted
//    step, for these methods); max_iterations limits those rows (our own test, status
//    max_iterations), and NLopt's maxeval is set to kEvaluationsPerIteration * max_iterations
//    as a guard against evaluations spent in line searches or MMA's inner iterations;
//  - ftol_abs = objective_tolerance and xtol_abs = step_tolerance are NLopt's own tests,
//    and xtol_rel = 1e-15 stops steps lost in round-off;
//  - ROUNDOFF_LIMITED (L-BFGS and SLSQP usually end there at a minimum) counts as converged
//    when the point passes a 100x looser stationarity test (KKT residual with least-squares
//    multipliers), as failed otherwise; so does a stall where NLopt evaluates the same point
//    over and over (MMA near the precision it can reach);
//  - the gradient test (projected gradient <= gradient_tolerance) is ours, done in the
//    objective callback, which then stops NLopt with nlopt::forced_stop. It is skipped when
//    there are general constraints: the objective's gradient does not vanish at a
//    constrained minimum, and NLopt exposes no multipliers.
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlopt.hpp>
#include <string>
#include <vector>

#include "forward/core/symmetric_eigen.hpp"
#include "optimizers/backend_detail.hpp"
#include "optimizers/backend_registry.hpp"

namespace tailor::detail {

namespace {

constexpr int kEvaluationsPerIteration = 10;

std::string result_name(nlopt::result result) {
  switch (result) {
    case nlopt::FAILURE:
      return "NLOPT_FAILURE";
    case nlopt::INVALID_ARGS:
      return "NLOPT_INVALID_ARGS";
    case nlopt::OUT_OF_MEMORY:
      return "NLOPT_OUT_OF_MEMORY";
    case nlopt::ROUNDOFF_LIMITED:
      return "NLOPT_ROUNDOFF_LIMITED";
    case nlopt::FORCED_STOP:
      return "NLOPT_FORCED_STOP";
    case nlopt::SUCCESS:
      return "NLOPT_SUCCESS";
    case nlopt::STOPVAL_REACHED:
      return "NLOPT_STOPVAL_REACHED";
    case nlopt::FTOL_REACHED:
      return "NLOPT_FTOL_REACHED (objective change <= objective_tolerance)";
    case nlopt::XTOL_REACHED:
      return "NLOPT_XTOL_REACHED (step <= step_tolerance or round-off)";
    case nlopt::MAXEVAL_REACHED:
      return "NLOPT_MAXEVAL_REACHED (maxeval = " + std::to_string(kEvaluationsPerIteration) +
             " x max_iterations)";
    case nlopt::MAXTIME_REACHED:
      return "NLOPT_MAXTIME_REACHED";
    default:
      return "NLopt result " + std::to_string(static_cast<int>(result));
  }
}

struct Context {
  Tracker& tracker;
  bool use_gradient_test;
  Vector last_z;    // the previous evaluation's point
  int repeats = 0;  // consecutive evaluations at last_z
};

// NLopt asks for the same point again and again: MMA does when its inner loop can no longer
// move the point in floating point (it would go on until maxeval).
constexpr int kMaxRepeats = 10;

struct ConstraintContext {
  Tracker& tracker;
  int index;
};

Vector to_vector(unsigned n, const double* x) { return Eigen::Map<const Vector>(x, n); }

// Stops NLopt from a callback. Throwing nlopt::forced_stop makes the C++ wrapper call
// force_stop() and return HUGE_VAL to NLopt; optimize() then throws it back to us.
[[noreturn]] void stop_nlopt() { throw nlopt::forced_stop(); }

// Stationarity at z for NLopt's ROUNDOFF_LIMITED verdict: the projected gradient of the
// Lagrangian, with least-squares multipliers for the active constraints (NLopt exposes none);
// +inf where z is infeasible or cannot be evaluated.
double kkt_residual(Tracker& tracker, const Vector& z) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  const int n = tracker.size();
  Vector g;
  if (!std::isfinite(tracker.value_and_gradient(z, g))) return inf;
  std::vector<Vector> normals;
  std::vector<bool> inequality;
  for (int i = 0; i < static_cast<int>(tracker.constraints().size()); ++i) {
    Vector a;
    const double c = tracker.constraint(i, z, &a);
    const bool equality = tracker.constraints()[i].equality;
    if (std::isnan(c) || (equality ? std::abs(c) : c) > kFeasibilityTolerance) return inf;
    if (equality || c >= -kFeasibilityTolerance) {
      normals.push_back(a);
      inequality.push_back(!equality);
    }
  }
  if (normals.empty()) return tracker.projected_gradient_norm(z, g);
  // Multipliers from the components not held by a bound (those are handled by projection).
  std::vector<int> free;
  for (int j = 0; j < n; ++j)
    if (z[j] > tracker.lower()[j] && z[j] < tracker.upper()[j]) free.push_back(j);
  Matrix A(free.size(), normals.size());
  Vector rhs(free.size());
  for (std::size_t r = 0; r < free.size(); ++r) {
    rhs[r] = -g[free[r]];
    for (std::size_t k = 0; k < normals.size(); ++k) A(r, k) = normals[k][free[r]];
  }
  Vector lambda = pivoted_qr_solve(A, rhs).x.col(0);
  for (std::size_t k = 0; k < normals.size(); ++k)  // an inequality cannot pull inwards
    if (inequality[k] && lambda[k] < 0.0) lambda[k] = 0.0;
  Vector lagrangian_gradient = g;
  for (std::size_t k = 0; k < normals.size(); ++k) lagrangian_gradient += lambda[k] * normals[k];
  return tracker.projected_gradient_norm(z, lagrangian_gradient);
}

double objective(unsigned n, const double* x, double* gradient, void* data) {
  auto& context = *static_cast<Context*>(data);
  Tracker& tracker = context.tracker;
  if (tracker.stop_requested()) stop_nlopt();
  const Vector z = to_vector(n, x);
  if (context.last_z.size() == z.size() && context.last_z == z) {
    if (++context.repeats >= kMaxRepeats) {
      const double residual = kkt_residual(tracker, z);
      char buffer[128];
      std::snprintf(buffer, sizeof buffer,
                    "no progress: NLopt evaluated the same point %d times (KKT residual %.3e)",
                    kMaxRepeats + 1, residual);
      tracker.request_stop(residual <= 100.0 * tracker.options().gradient_tolerance
                               ? OptimizerStatus::converged
                               : OptimizerStatus::failed,
                           buffer);
      stop_nlopt();
    }
  } else {
    context.last_z = z;
    context.repeats = 0;
  }
  const int best_updates = tracker.best_updates();
  double f;
  if (gradient) {
    Vector g;
    f = tracker.value_and_gradient(z, g);
    Eigen::Map<Vector>(gradient, n) = g;
  } else {
    f = tracker.value(z);
  }
  // A failed evaluation is +inf with a zero gradient: the line search / MMA's inner loop
  // sees an infinitely bad point and shortens the step.
  if (tracker.stop_requested()) stop_nlopt();

  // The gradient test at every evaluation with a gradient, improving or not: near the
  // minimum, round-off may keep the objective from improving while the gradient is tiny.
  if (context.use_gradient_test && gradient && std::isfinite(f)) {
    const double norm = tracker.projected_gradient_norm(z, Eigen::Map<const Vector>(gradient, n));
    if (norm <= tracker.options().gradient_tolerance) {
      if (tracker.best_updates() != best_updates) tracker.record_iteration(z, f);
      char buffer[96];
      std::snprintf(buffer, sizeof buffer, "projected gradient norm %.3e <= gradient_tolerance", norm);
      tracker.request_stop(OptimizerStatus::converged, buffer);
      stop_nlopt();
    }
  }
  if (tracker.best_updates() != best_updates) {  // z is the new best point
    tracker.record_iteration(z, f);
    if (tracker.iterations() >= tracker.options().max_iterations) {
      tracker.request_stop(OptimizerStatus::max_iterations,
                           "reached max_iterations = " + std::to_string(tracker.options().max_iterations) +
                               " (improving evaluations)");
      stop_nlopt();
    }
  }
  return f;
}

double constraint(unsigned n, const double* x, double* gradient, void* data) {
  auto& context = *static_cast<ConstraintContext*>(data);
  const Vector z = to_vector(n, x);
  Vector g;
  const double c = context.tracker.constraint(context.index, z, gradient ? &g : nullptr);
  if (context.tracker.stop_requested()) stop_nlopt();
  if (std::isnan(c)) {
    // Cannot be evaluated: report a violated constraint pointing nowhere.
    if (gradient) Eigen::Map<Vector>(gradient, n).setZero();
    return HUGE_VAL;
  }
  if (gradient) Eigen::Map<Vector>(gradient, n) = g;
  return c;
}

}  // namespace

BackendOutcome run_nlopt(Tracker& tracker, const Vector& z0) {
  const OptimizerOptions& options = tracker.options();
  nlopt::algorithm algorithm = nlopt::LD_LBFGS;
  if (options.backend == OptimizerBackend::nlopt_mma) algorithm = nlopt::LD_MMA;
  if (options.backend == OptimizerBackend::nlopt_slsqp) algorithm = nlopt::LD_SLSQP;

  for (const auto& c : tracker.constraints()) {
    if (algorithm == nlopt::LD_LBFGS)
      return {OptimizerStatus::failed,
              "NLopt L-BFGS supports bounds only; constraint '" + c.name +
                  "' needs nlopt_mma (inequalities) or nlopt_slsqp",
              std::nullopt};
    if (algorithm == nlopt::LD_MMA && c.equality)
      return {OptimizerStatus::failed,
              "NLopt MMA supports inequality constraints only; equality constraint '" + c.name +
                  "' needs nlopt_slsqp or ipopt",
              std::nullopt};
  }

  // NLopt would take +inf with a zero gradient at the start for a stationary point. NLopt's
  // own first evaluation at z0 is then served from the Tracker's cache.
  Vector g0;
  const double f0 = tracker.value_and_gradient(z0, g0);
  if (!std::isfinite(f0))
    return {OptimizerStatus::failed, "the objective cannot be evaluated at the starting point", std::nullopt};
  tracker.record_iteration(z0, f0);  // resuming: the checkpoint's row, not written again

  const unsigned n = static_cast<unsigned>(tracker.size());
  nlopt::opt opt(algorithm, n);
  Context context{tracker, tracker.constraints().empty(), Vector(), 0};
  opt.set_min_objective(objective, &context);
  if (tracker.has_finite_bounds()) {
    opt.set_lower_bounds(std::vector<double>(tracker.lower().data(), tracker.lower().data() + n));
    opt.set_upper_bounds(std::vector<double>(tracker.upper().data(), tracker.upper().data() + n));
  }
  std::vector<ConstraintContext> constraint_contexts;
  constraint_contexts.reserve(tracker.constraints().size());  // stable addresses
  for (int i = 0; i < static_cast<int>(tracker.constraints().size()); ++i) {
    constraint_contexts.push_back({tracker, i});
    // Feasibility tolerance: a little below the Tracker's, so that NLopt's answer ranks as
    // feasible there too.
    if (tracker.constraints()[i].equality)
      opt.add_equality_constraint(constraint, &constraint_contexts.back(), 1e-8);
    else
      opt.add_inequality_constraint(constraint, &constraint_contexts.back(), 1e-8);
  }
  // Resuming, the iterations before the checkpoint count.
  const int max_iterations = std::max(options.max_iterations - tracker.iterations(), 1);
  opt.set_maxeval(max_iterations > 100000000 / kEvaluationsPerIteration
                      ? 100000000
                      : kEvaluationsPerIteration * max_iterations);
  if (options.objective_tolerance > 0.0) opt.set_ftol_abs(options.objective_tolerance);
  if (options.step_tolerance > 0.0) opt.set_xtol_abs(options.step_tolerance);
  // Stagnation guard: a step below round-off is no step. Without it MMA can re-evaluate the
  // same point until maxeval.
  opt.set_xtol_rel(1e-15);

  std::vector<double> x(z0.data(), z0.data() + n);
  double f = 0.0;
  nlopt::result result = nlopt::FAILURE;
  std::string extra;
  try {
    result = opt.optimize(x, f);
  } catch (const nlopt::forced_stop&) {
    result = nlopt::FORCED_STOP;  // the reason is in the Tracker
  } catch (const nlopt::roundoff_limited&) {
    result = nlopt::ROUNDOFF_LIMITED;
  } catch (const std::invalid_argument& e) {
    result = nlopt::INVALID_ARGS;
    extra = std::string(": ") + e.what();
  } catch (const std::bad_alloc&) {
    result = nlopt::OUT_OF_MEMORY;
  } catch (const std::runtime_error& e) {
    result = nlopt::FAILURE;
    extra = std::string(": ") + e.what();
  }

  // After a stop from a callback some algorithms report a failure (L-BFGS sees the HUGE_VAL
  // the wrapper returns); the Tracker holds the real reason.
  if (tracker.stop_status()) {
    result = nlopt::FORCED_STOP;
    extra.clear();
  }

  BackendOutcome outcome;
  outcome.message =
      result_name(result) + extra + ", " + std::to_string(opt.get_numevals()) + " NLopt evaluations";
  outcome.final_point = Eigen::Map<const Vector>(x.data(), n);
  switch (result) {
    case nlopt::SUCCESS:
    case nlopt::STOPVAL_REACHED:
    case nlopt::FTOL_REACHED:
    case nlopt::XTOL_REACHED:
      outcome.status = OptimizerStatus::converged;
      break;
    case nlopt::MAXEVAL_REACHED:
      outcome.status = OptimizerStatus::max_iterations;
      break;
    case nlopt::MAXTIME_REACHED:
      outcome.status = OptimizerStatus::time_limit;
      break;
    case nlopt::ROUNDOFF_LIMITED: {
      // L-BFGS and SLSQP typically end here at a minimum: no further progress is possible in
      // floating point. Converged if NLopt's point passes a 100x looser stationarity test.
      const double residual = kkt_residual(tracker, *outcome.final_point);
      char buffer[96];
      std::snprintf(buffer, sizeof buffer, "; KKT residual %.3e", residual);
      outcome.message += buffer;
      outcome.status = residual <= 100.0 * options.gradient_tolerance ? OptimizerStatus::converged
                                                                      : OptimizerStatus::failed;
      break;
    }
    default:
      outcome.status = OptimizerStatus::failed;
      break;
  }
  return outcome;
}

}  // namespace tailor::detail

namespace tailor {

// The registry's entries (optimizers/backend_registry.hpp).
BackendEntry nlopt_lbfgs_backend_entry() {
  return {
      "nlopt_lbfgs", "NLopt LD_LBFGS: limited-memory BFGS with bounds", {.bounds = true}, &detail::run_nlopt};
}

BackendEntry nlopt_mma_backend_entry() {
  return {"nlopt_mma",
          "NLopt LD_MMA: method of moving asymptotes, bounds and inequality constraints",
          {.bounds = true, .inequality_constraints = true},
          &detail::run_nlopt};
}

BackendEntry nlopt_slsqp_backend_entry() {
  return {"nlopt_slsqp",
          "NLopt LD_SLSQP: sequential quadratic programming, bounds and all constraints",
          {.bounds = true, .inequality_constraints = true, .equality_constraints = true},
          &detail::run_nlopt};
}

}  // namespace tailor
