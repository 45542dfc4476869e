// Ceres back-ends:
//  - ceres_lbfgs: GradientProblemSolver with L-BFGS directions and a Wolfe line search.
//    Ceres's line-search minimizer has no bounds, so finite bounds are refused.
//  - ceres_least_squares: Levenberg-Marquardt (DENSE_QR) on the residual form
//    J = 1/2 ||r(z)||^2, one residual block over the single parameter block z; bounds through
//    SetParameterLowerBound/UpperBound, refined by an active-set loop (see below).
//
// Tolerances: Ceres's gradient tolerance is absolute on |z - P(z - g)|_inf like ours; its
// function tolerance is relative (|dJ| <= tol * J), so objective_tolerance is divided by the
// starting objective (which makes it stricter as J decreases); its parameter tolerance is
// relative too (|dz| <= tol * |z|), so step_tolerance is divided by max(1, |z0|). A zero
// tolerance switches the test off.
#include <ceres/ceres.h>

#include <cmath>
#include <string>

#include "optimizers/backend_detail.hpp"
#include "optimizers/backend_registry.hpp"

namespace tailor::detail {

namespace {

constexpr int kMaxActiveSetRounds = 10;

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// One history row per Ceres iteration (successful or not: the iterate is then unchanged);
// stops Ceres when the Tracker asks to. update_state_every_iteration makes `z` current.
class TrackingCallback : public ceres::IterationCallback {
 public:
  // skip_first_row: a restarted solve's iteration 0 is the previous solve's last iterate.
  // keep_radius: the trust-region radius is the back-end state a resumed run takes back.
  TrackingCallback(Tracker& tracker, const double* z, bool skip_first_row = false, bool keep_radius = false)
      : tracker_(tracker), z_(z), skip_first_row_(skip_first_row), keep_radius_(keep_radius) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    if (keep_radius_) tracker_.set_backend_state("trust_region_radius", summary.trust_region_radius);
    if (summary.iteration > 0 || !skip_first_row_) {
      tracker_.record_iteration(Eigen::Map<const Vector>(z_, tracker_.size()), summary.cost,
                                summary.gradient_max_norm);
    }
    if (!tracker_.stop_requested()) return ceres::SOLVER_CONTINUE;
    // Interrupted or out of time: the current iterate is usable. A failure is not.
    return *tracker_.stop_status() == OptimizerStatus::failed ? ceres::SOLVER_ABORT
                                                              : ceres::SOLVER_TERMINATE_SUCCESSFULLY;
  }

 private:
  Tracker& tracker_;
  const double* z_;
  bool skip_first_row_;
  bool keep_radius_;
};

class Objective : public ceres::FirstOrderFunction {
 public:
  explicit Objective(Tracker& tracker) : tracker_(tracker) {}
  // false tells Ceres the point cannot be evaluated; its line search then shortens the step.
  bool Evaluate(const double* parameters, double* cost, double* gradient) const override {
    const Vector z = Eigen::Map<const Vector>(parameters, tracker_.size());
    if (gradient) {
      Vector g;
      *cost = tracker_.value_and_gradient(z, g);
      Eigen::Map<Vector>(gradient, tracker_.size()) = g;
    } else {
      *cost = tracker_.value(z);
    }
    return std::isfinite(*cost);
  }
  int NumParameters() const override { return tracker_.size(); }

 private:
  Tracker& tracker_;
};

class Residuals : public ceres::CostFunction {
 public:
  Residuals(Tracker& tracker, int num_residuals) : tracker_(tracker) {
    set_num_residuals(num_residuals);
    mutable_parameter_block_sizes()->push_back(tracker.size());
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const int n = tracker_.size(), m = num_residuals();
    const Vector z = Eigen::Map<const Vector>(parameters[0], n);
    const bool want_jacobian = jacobians && jacobians[0];
    Vector r;
    Matrix J;
    if (!tracker_.residuals(z, r, want_jacobian ? &J : nullptr)) return false;
    if (r.size() != m || (want_jacobian && (J.rows() != m || J.cols() != n))) {
      tracker_.request_stop(OptimizerStatus::failed,
                            "residuals() returned sizes that disagree with num_residuals()");
      return false;
    }
    Eigen::Map<Vector>(residuals, m) = r;
    if (want_jacobian) Eigen::Map<RowMajorMatrix>(jacobians[0], m, n) = J;
    return true;
  }

 private:
  Tracker& tracker_;
};

OptimizerStatus map_termination(ceres::TerminationType type) {
  switch (type) {
    case ceres::CONVERGENCE:
      return OptimizerStatus::converged;
    case ceres::NO_CONVERGENCE:
      return OptimizerStatus::max_iterations;
    default:
      return OptimizerStatus::failed;  // FAILURE, USER_*: the Tracker knows why
  }
}

template <typename CeresOptions>
void set_common_options(CeresOptions& ceres_options, const Tracker& tracker, double f0, const Vector& z0,
                        TrackingCallback* callback) {
  const OptimizerOptions& options = tracker.options();
  // Resuming, the iterations before the checkpoint count, and the relative function
  // tolerance refers to the run's first objective.
  ceres_options.max_num_iterations = std::max(options.max_iterations - tracker.iterations(), 0);
  ceres_options.gradient_tolerance = std::max(options.gradient_tolerance, 0.0);
  const double first = tracker.first_objective(f0);
  ceres_options.function_tolerance = options.objective_tolerance > 0.0
                                         ? options.objective_tolerance / std::max(std::abs(first), 1e-300)
                                         : 0.0;
  ceres_options.parameter_tolerance =
      options.step_tolerance > 0.0 ? options.step_tolerance / std::max(1.0, z0.norm()) : 0.0;
  ceres_options.logging_type = ceres::SILENT;
  ceres_options.minimizer_progress_to_stdout = false;
  ceres_options.update_state_every_iteration = true;
  ceres_options.callbacks.push_back(callback);
}

}  // namespace

BackendOutcome run_ceres_lbfgs(Tracker& tracker, const Vector& z0) {
  if (!tracker.constraints().empty())
    return {OptimizerStatus::failed, "ceres_lbfgs supports neither constraints nor bounds", std::nullopt};
  if (tracker.has_finite_bounds())
    return {OptimizerStatus::failed,
            "ceres_lbfgs does not support bounds (Ceres's line-search minimizer is "
            "unconstrained); use nlopt_lbfgs, ipopt or ceres_least_squares",
            std::nullopt};
  Vector g0;  // with the gradient: Ceres asks for it first, then gets it from the cache
  const double f0 = tracker.value_and_gradient(z0, g0);
  if (!std::isfinite(f0))
    return {OptimizerStatus::failed, "the objective cannot be evaluated at the starting point", std::nullopt};

  Vector z = z0;
  TrackingCallback callback(tracker, z.data());
  ceres::GradientProblemSolver::Options ceres_options;
  ceres_options.line_search_direction_type = ceres::LBFGS;
  set_common_options(ceres_options, tracker, f0, z0, &callback);

  ceres::GradientProblem problem(new Objective(tracker));  // takes ownership
  ceres::GradientProblemSolver::Summary summary;
  ceres::Solve(ceres_options, problem, z.data(), &summary);
  return {map_termination(summary.termination_type), summary.BriefReport() + " (" + summary.message + ")", z};
}

BackendOutcome run_ceres_least_squares(Tracker& tracker, const Vector& z0) {
  ReducedFunctional& functional = tracker.functional();
  if (!functional.has_residuals() || functional.num_residuals() <= 0)
    return {OptimizerStatus::failed,
            "ceres_least_squares needs the residual form (has_residuals()), which this "
            "functional does not offer",
            std::nullopt};
  if (!tracker.constraints().empty())
    return {OptimizerStatus::failed, "ceres_least_squares supports bounds only, not general constraints",
            std::nullopt};

  Vector r;
  Matrix J0;  // with the Jacobian: Ceres's first request is then served from the cache
  if (!tracker.residuals(z0, r, &J0))
    return {OptimizerStatus::failed, "the residuals cannot be evaluated at the starting point", std::nullopt};
  const double f0 = 0.5 * r.squaredNorm();
  const int n = tracker.size();

  // Ceres projects its Levenberg-Marquardt steps onto the bounds, but the step itself is
  // computed as if the variables at a bound could move; when the minimum lies on a bound it
  // stalls short of it (5e-3 off on the bounded Rosenbrock test). So: an active-set loop.
  // Solve, hold the variables that sit on a bound and push against it constant
  // (SubsetManifold), release those that pull inwards, and solve again until the set settles.
  Vector z = z0;
  std::vector<int> held;
  ceres::Solver::Summary summary;
  int rounds = 0;
  for (; rounds < kMaxActiveSetRounds; ++rounds) {
    ceres::Problem problem;  // owns the cost function and the manifold
    problem.AddResidualBlock(new Residuals(tracker, functional.num_residuals()), nullptr, z.data());
    for (int i = 0; i < n; ++i) {
      if (std::isfinite(tracker.lower()[i])) problem.SetParameterLowerBound(z.data(), i, tracker.lower()[i]);
      if (std::isfinite(tracker.upper()[i])) problem.SetParameterUpperBound(z.data(), i, tracker.upper()[i]);
    }
    if (!held.empty()) problem.SetManifold(z.data(), new ceres::SubsetManifold(n, held));

    TrackingCallback callback(tracker, z.data(), /*skip_first_row=*/rounds > 0, /*keep_radius=*/true);
    ceres::Solver::Options ceres_options;
    ceres_options.minimizer_type = ceres::TRUST_REGION;
    ceres_options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    ceres_options.linear_solver_type = ceres::DENSE_QR;
    ceres_options.num_threads = 1;
    set_common_options(ceres_options, tracker, f0, z0, &callback);
    // Resuming, the first solve continues with the checkpoint's trust region.
    if (const auto radius = tracker.resumed_state("trust_region_radius"); radius && rounds == 0)
      ceres_options.initial_trust_region_radius = *radius;
    ceres::Solve(ceres_options, &problem, &summary);
    if (tracker.stop_status() || summary.termination_type != ceres::CONVERGENCE ||
        !tracker.has_finite_bounds())
      break;

    // The active set at the solution, from the gradient J^T r. A variable within round-off
    // of a bound counts as on it (and is put exactly there).
    Matrix J;
    if (!tracker.residuals(z, r, &J)) break;
    const Vector g = J.transpose() * r;
    std::vector<int> active;
    for (int i = 0; i < n; ++i) {
      const double lower = tracker.lower()[i], upper = tracker.upper()[i];
      if (z[i] <= lower + 1e-12 * std::max(1.0, std::abs(lower)) && g[i] > 0.0) {
        z[i] = lower;
        active.push_back(i);
      } else if (z[i] >= upper - 1e-12 * std::max(1.0, std::abs(upper)) && g[i] < 0.0) {
        z[i] = upper;
        active.push_back(i);
      }
    }
    if (active == held || static_cast<int>(active.size()) == n) break;  // settled, or a vertex
    held = std::move(active);
  }
  std::string message = summary.BriefReport() + " (" + summary.message + ")";
  if (rounds > 0) message += ", " + std::to_string(rounds + 1) + " active-set rounds";
  return {map_termination(summary.termination_type), message, z};
}

}  // namespace tailor::detail

namespace tailor {

// The registry's entries (optimizers/backend_registry.hpp).
BackendEntry ceres_lbfgs_backend_entry() {
  return {"ceres_lbfgs",
          "Ceres GradientProblemSolver, L-BFGS line search; no bounds",
          {},
          &detail::run_ceres_lbfgs};
}

BackendEntry ceres_least_squares_backend_entry() {
  return {"ceres_least_squares",
          "Ceres trust-region Levenberg-Marquardt on the residual form, bounds",
          {.bounds = true},
          &detail::run_ceres_least_squares};
}

}  // namespace tailor
