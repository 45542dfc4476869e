// minimize(): validation, dispatch to a back-end, SIGINT handling, and the shared Tracker
// (see backend_detail.hpp for what it does and why); OptimizerResult::report().
#include <signal.h>  // sigaction

#include <cmath>
#include <csignal>
#include <cstdio>
#include <limits>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include "forward/core/format_number.hpp"
#include "optimizers/backend_detail.hpp"
#include "optimizers/optimizer.hpp"

namespace tailor {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct BackendName {
  OptimizerBackend backend;
  const char* name;
};
constexpr BackendName kBackendNames[] = {
    {OptimizerBackend::ipopt, "ipopt"},
    {OptimizerBackend::nlopt_lbfgs, "nlopt_lbfgs"},
    {OptimizerBackend::nlopt_mma, "nlopt_mma"},
    {OptimizerBackend::nlopt_slsqp, "nlopt_slsqp"},
    {OptimizerBackend::ceres_lbfgs, "ceres_lbfgs"},
    {OptimizerBackend::ceres_least_squares, "ceres_least_squares"},
    {OptimizerBackend::gradient_descent, "gradient_descent"},
};

// SIGINT: the handler only sets a flag (nothing else is async-signal-safe); the Tracker polls
// it after every evaluation and iteration, and the back-end is stopped through its own API.
volatile std::sig_atomic_t g_interrupted = 0;
void on_sigint(int) { g_interrupted = 1; }

// Installs the handler for one minimize() call and restores the previous one afterwards. A
// pending interrupt from an enclosing minimize() (a functional that optimizes internally) is
// kept, and an interrupt received here is passed on to it: Ctrl-C means "stop everything".
class SigintGuard {
 public:
  SigintGuard() : outer_flag_(g_interrupted) {
    g_interrupted = 0;
    struct sigaction action {};
    action.sa_handler = on_sigint;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;  // a Ctrl-C must not make the solver's I/O fail with EINTR
    installed_ = sigaction(SIGINT, &action, &previous_) == 0;
  }
  ~SigintGuard() {
    if (installed_) sigaction(SIGINT, &previous_, nullptr);
    if (outer_flag_) g_interrupted = 1;
  }
  SigintGuard(const SigintGuard&) = delete;
  SigintGuard& operator=(const SigintGuard&) = delete;

 private:
  std::sig_atomic_t outer_flag_;
  struct sigaction previous_ {};
  bool installed_ = false;
};

}  // namespace

std::string to_string(OptimizerBackend backend) {
  for (const auto& entry : kBackendNames)
    if (entry.backend == backend) return entry.name;
  return "unknown";
}

OptimizerBackend parse_optimizer_backend(const std::string& name) {
  std::string known;
  for (const auto& entry : kBackendNames) {
    if (name == entry.name) return entry.backend;
    known += known.empty() ? "" : ", ";
    known += entry.name;
  }
  throw std::invalid_argument("unknown optimizer back-end '" + name + "' (known: " + known + ")");
}

std::string to_string(OptimizerStatus status) {
  switch (status) {
    case OptimizerStatus::converged:
      return "converged";
    case OptimizerStatus::max_iterations:
      return "max_iterations";
    case OptimizerStatus::time_limit:
      return "time_limit";
    case OptimizerStatus::interrupted:
      return "interrupted";
    case OptimizerStatus::failed:
      return "failed";
  }
  return "unknown";
}

std::string OptimizerResult::report() const {
  std::ostringstream out;
  out << "Optimizer report\n";
  // The message starts with the back-end's name ("nlopt_lbfgs: ..."), see minimize().
  const auto colon = message.find(": ");
  if (colon != std::string::npos) {
    try {
      out << "  backend        : " << to_string(parse_optimizer_backend(message.substr(0, colon))) << '\n';
    } catch (const std::invalid_argument&) {
    }
  }
  out << "  status         : " << to_string(status) << '\n';
  out << "  message        : " << message << '\n';
  const int iterations = history.empty() ? 0 : history.back().iteration;
  out << "  iterations     : " << iterations << '\n';
  out << "  evaluations    : " << evaluations << '\n';
  if (failed_evaluations > 0)
    out << "  failed points  : " << failed_evaluations << " (forward solve failed; the step was shortened)\n";
  out << "  objective      : ";
  if (!history.empty()) out << format_number(history.front().objective, "%.6e") << " -> ";
  out << format_number(objective, "%.6e") << '\n';
  if (!history.empty()) {
    out << "  gradient norm  : " << format_number(history.back().gradient_norm, "%.3e")
        << " (projected, last iteration)\n";
  }
  out << "  time           : " << format_number(seconds, "%.3f") << " s\n";
  if (!history.empty()) {
    out << "  solves         : " << history.back().forward_solves << " forward, "
        << history.back().adjoint_solves << " adjoint\n";
  }
  return out.str();
}

namespace detail {

bool interrupt_received() { return g_interrupted != 0; }

// ---------------------------------------------------------------------------------------------
// Tracker

Tracker::Tracker(ReducedFunctional& functional, const Bounds& bounds,
                 const std::vector<Constraint>& constraints, const OptimizerOptions& options)
    : functional_(functional),
      constraints_(constraints),
      options_(options),
      n_(functional.size()),
      lower_(bounds.lower.size() == functional.size() ? bounds.lower
                                                      : Vector::Constant(functional.size(), -kInf)),
      upper_(bounds.upper.size() == functional.size() ? bounds.upper
                                                      : Vector::Constant(functional.size(), kInf)),
      start_(std::chrono::steady_clock::now()),
      start_forward_(functional.counters().forward_solves),
      start_adjoint_(functional.counters().adjoint_solves) {}

bool Tracker::has_finite_bounds() const {
  return lower_.array().isFinite().any() || upper_.array().isFinite().any();
}

Vector Tracker::project(const Vector& z) const { return z.cwiseMax(lower_).cwiseMin(upper_); }

double Tracker::seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Tracker::fail(const std::string& what) {
  request_stop(OptimizerStatus::failed, "functional failed: " + what);
}

double Tracker::value(const Vector& z) {
  if (value_cache_ && value_cache_->first == z) return value_cache_->second;
  if (gradient_z_ && *gradient_z_ == z) return gradient_f_;
  ++evaluations_;
  double f = kInf;
  try {
    f = functional_.value(z);
  } catch (const EvaluationError&) {
    f = kInf;  // an infinitely bad point: the back-end shortens its step
  } catch (const std::exception& e) {
    fail(e.what());
  } catch (...) {
    fail("unknown exception");
  }
  if (!std::isfinite(f)) {
    f = kInf;
    ++failed_evaluations_;
  }
  value_cache_.emplace(z, f);
  consider(z, f);
  return f;
}

double Tracker::value_and_gradient(const Vector& z, Vector& gradient) {
  if (gradient_z_ && *gradient_z_ == z) {
    gradient = gradient_;
    return gradient_f_;
  }
  ++evaluations_;
  double f = kInf;
  gradient.setZero(n_);
  try {
    f = functional_.value_and_gradient(z, gradient);
  } catch (const EvaluationError&) {
    f = kInf;
  } catch (const std::exception& e) {
    fail(e.what());
  } catch (...) {
    fail("unknown exception");
  }
  if (!std::isfinite(f) || gradient.size() != n_ || !gradient.allFinite()) {
    f = kInf;
    ++failed_evaluations_;
    gradient.setZero(n_);
  } else {
    gradient_z_ = z;
    gradient_ = gradient;
    gradient_f_ = f;
  }
  value_cache_.emplace(z, f);
  consider(z, f);
  return f;
}

bool Tracker::residuals(const Vector& z, Vector& r, Matrix* jacobian) {
  const bool cached = residual_z_ && *residual_z_ == z && (!jacobian || residual_jacobian_);
  if (!cached) {
    ++evaluations_;
    bool ok = false;
    Matrix J;
    try {
      functional_.residuals(z, residual_r_, jacobian ? &J : nullptr);
      ok = residual_r_.allFinite() && (!jacobian || J.allFinite());
    } catch (const EvaluationError&) {
    } catch (const std::exception& e) {
      fail(e.what());
    } catch (...) {
      fail("unknown exception");
    }
    residual_z_ = z;
    residual_ok_ = ok;
    if (!ok) ++failed_evaluations_;
    if (jacobian && ok)
      residual_jacobian_ = std::move(J);
    else
      residual_jacobian_.reset();
    const double f = ok ? 0.5 * residual_r_.squaredNorm() : kInf;
    value_cache_.emplace(z, f);
    if (ok && residual_jacobian_) {
      gradient_z_ = z;
      gradient_ = residual_jacobian_->transpose() * residual_r_;
      gradient_f_ = f;
    }
    consider(z, f);
  }
  if (!residual_ok_) return false;
  r = residual_r_;
  if (jacobian) *jacobian = *residual_jacobian_;
  return true;
}

double Tracker::constraint(int i, const Vector& z, Vector* gradient) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  try {
    if (gradient) gradient->setZero(n_);
    const double c = constraints_[i].evaluate(z, gradient);
    return std::isfinite(c) && (!gradient || gradient->allFinite()) ? c : nan;
  } catch (const EvaluationError&) {
    return nan;
  } catch (const std::exception& e) {
    request_stop(OptimizerStatus::failed, "constraint '" + constraints_[i].name + "' failed: " + e.what());
  } catch (...) {
    request_stop(OptimizerStatus::failed, "constraint '" + constraints_[i].name + "' failed");
  }
  return nan;
}

double Tracker::violation(const Vector& z) {
  double v = std::max((lower_ - z).maxCoeff(), (z - upper_).maxCoeff());
  v = std::max(v, 0.0);
  for (int i = 0; i < static_cast<int>(constraints_.size()); ++i) {
    const double c = constraint(i, z, nullptr);
    if (std::isnan(c)) return kInf;
    v = std::max(v, constraints_[i].equality ? std::abs(c) : c);
  }
  return v;
}

void Tracker::consider(const Vector& z, double f) {
  if (!std::isfinite(f)) return;
  bool better = false;
  double v = 0.0;
  if (constraints_.empty()) {
    // Bounds only: back-ends stay inside the box up to Ipopt's tiny relaxation.
    better = (!has_best_ || f < best_f_) && violation(z) <= kFeasibilityTolerance;
  } else {
    const bool best_feasible = has_best_ && best_violation_ <= kFeasibilityTolerance;
    if (best_feasible && f >= best_f_) return;  // cannot win: skip the constraint evaluations
    v = violation(z);
    if (!has_best_)
      better = true;
    else if (v <= kFeasibilityTolerance)
      better = !best_feasible || f < best_f_;
    else
      better = !best_feasible && (v < best_violation_ || (v == best_violation_ && f < best_f_));
  }
  if (better) {
    has_best_ = true;
    best_z_ = z;
    best_f_ = f;
    best_violation_ = v;
    ++best_updates_;
  }
}

std::optional<double> Tracker::known_value(const Vector& z) const {
  if (has_best_ && best_z_ == z) return best_f_;
  if (value_cache_ && value_cache_->first == z) return value_cache_->second;
  if (gradient_z_ && *gradient_z_ == z) return gradient_f_;
  return std::nullopt;
}

double Tracker::projected_gradient_norm(const Vector& z, const Vector& gradient) const {
  return (z - project(z - gradient)).lpNorm<Eigen::Infinity>();
}

const Vector* Tracker::cached_gradient(const Vector& z) const {
  return gradient_z_ && *gradient_z_ == z ? &gradient_ : nullptr;
}

void Tracker::record_iteration(const Vector& z, double f, double fallback_gradient_norm) {
  OptimizerIteration row;
  row.iteration = static_cast<int>(history_.size());
  // Our own value where we have it: back-ends may report a rescaled objective (Ipopt) or the
  // cost of a rejected trial point (Ceres' trust region).
  const auto known = known_value(z);
  row.objective = known ? *known : f;
  const Vector* g = cached_gradient(z);
  row.gradient_norm = g ? projected_gradient_norm(z, *g) : fallback_gradient_norm;
  row.step_norm = history_.empty() ? 0.0 : (z - last_row_z_).lpNorm<Eigen::Infinity>();
  row.seconds = seconds();
  // Solves of this run only: the functional's counters may include earlier work.
  row.forward_solves = functional_.counters().forward_solves - start_forward_;
  row.adjoint_solves = functional_.counters().adjoint_solves - start_adjoint_;
  history_.push_back(row);
  last_row_z_ = z;
  print_row(row);
}

void Tracker::print_row(const OptimizerIteration& row) {
  if (!options_.progress) return;
  char line[160];
  if (row.iteration == 0) {
    std::snprintf(line, sizeof line, "%5s  %14s  %10s  %10s  %9s  %8s  %8s\n", "iter", "objective",
                  "|proj g|", "|step|", "time[s]", "forward", "adjoint");
    *options_.progress << line;
  }
  std::snprintf(line, sizeof line, "%5d  %14.7e  %10.3e  %10.3e  %9.3f  %8d  %8d\n", row.iteration,
                row.objective, row.gradient_norm, row.step_norm, row.seconds, row.forward_solves,
                row.adjoint_solves);
  *options_.progress << line << std::flush;
}

void Tracker::apply_change_tests() {
  if (history_.size() < 2 || stop_status_) return;
  const auto& last = history_.back();
  const double change = std::abs(last.objective - history_[history_.size() - 2].objective);
  if (options_.objective_tolerance > 0.0 && change <= options_.objective_tolerance) {
    request_stop(OptimizerStatus::converged,
                 "objective change " + format_number(change, "%.3e") + " <= objective_tolerance");
  } else if (options_.step_tolerance > 0.0 && last.step_norm <= options_.step_tolerance) {
    request_stop(OptimizerStatus::converged,
                 "step " + format_number(last.step_norm, "%.3e") + " <= step_tolerance");
  }
}

bool Tracker::stop_requested() {
  if (stop_status_) return true;
  if (interrupt_received()) {
    request_stop(OptimizerStatus::interrupted, "interrupted (SIGINT)");
  } else if (options_.time_limit_seconds > 0.0 && seconds() > options_.time_limit_seconds) {
    request_stop(OptimizerStatus::time_limit,
                 "time limit of " + format_number(options_.time_limit_seconds, "%g") + " s reached");
  }
  return stop_status_.has_value();
}

void Tracker::request_stop(OptimizerStatus status, const std::string& message) {
  if (stop_status_) return;  // the first reason is the real one
  stop_status_ = status;
  stop_message_ = message;
}

}  // namespace detail

OptimizerResult minimize(ReducedFunctional& functional, const Vector& z0, const Bounds& bounds,
                         const std::vector<Constraint>& constraints, const OptimizerOptions& options) {
  SigintGuard sigint_guard;
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
