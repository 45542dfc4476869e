#include "optimizers/tracker.hpp"

#include <cmath>
#include <cstdio>
#include <ostream>

#include "forward/core/format_number.hpp"
#include "optimizers/interrupt.hpp"

namespace tailor::detail {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

Tracker::Tracker(ReducedFunctional& functional, const Bounds& bounds,
                 const std::vector<Constraint>& constraints, const OptimizerOptions& options,
                 const OptimizerCheckpoint* resume)
    : functional_(functional),
      constraints_(constraints),
      options_(options),
      n_(functional.size()),
      lower_(bounds.lower.size() == functional.size() ? bounds.lower
                                                      : Vector::Constant(functional.size(), -kInf)),
      upper_(bounds.upper.size() == functional.size() ? bounds.upper
                                                      : Vector::Constant(functional.size(), kInf)),
      start_(std::chrono::steady_clock::now()),
      start_counters_(functional.counters()) {
  if (!resume) return;
  history_ = resume->history;
  last_row_z_ = resume->z;
  evaluations_ = resume->evaluations;
  failed_evaluations_ = resume->failed_evaluations;
  if (resume->best_z.size() == n_) {
    has_best_ = true;
    best_z_ = resume->best_z;
    best_f_ = resume->best_objective;
    best_violation_ = resume->best_violation;
  }
  seconds_offset_ = resume->seconds;
  counters_offset_ = resume->counters;
  resumed_from_ = resume->iteration;
  skip_resumed_row_ = true;
  resumed_state_ = resume->backend_state;
  backend_state_ = resume->backend_state;
  last_checkpoint_ = resume->iteration;
}

bool Tracker::has_finite_bounds() const {
  return lower_.array().isFinite().any() || upper_.array().isFinite().any();
}

Vector Tracker::project(const Vector& z) const { return z.cwiseMax(lower_).cwiseMin(upper_); }

double Tracker::seconds() const {
  return seconds_offset_ + std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

FunctionalCounters Tracker::counters() const {
  const FunctionalCounters& now = functional_.counters();
  FunctionalCounters out = counters_offset_;
  out.evaluations += now.evaluations - start_counters_.evaluations;
  out.forward_solves += now.forward_solves - start_counters_.forward_solves;
  out.adjoint_solves += now.adjoint_solves - start_counters_.adjoint_solves;
  out.forward_seconds += now.forward_seconds - start_counters_.forward_seconds;
  out.adjoint_seconds += now.adjoint_seconds - start_counters_.adjoint_seconds;
  out.factorizations += now.factorizations - start_counters_.factorizations;
  out.back_solves += now.back_solves - start_counters_.back_solves;
  out.hessian_vectors += now.hessian_vectors - start_counters_.hessian_vectors;
  return out;
}

std::optional<double> Tracker::resumed_state(const std::string& name) const {
  const auto it = resumed_state_.find(name);
  if (it == resumed_state_.end()) return std::nullopt;
  return it->second;
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

bool Tracker::curvature_product(const Vector& z, const Vector& v, bool gauss_newton, Vector& out) {
  try {
    out = gauss_newton ? functional_.gauss_newton_vector(z, v) : functional_.hessian_vector(z, v);
    return out.size() == n_ && out.allFinite();
  } catch (const EvaluationError&) {
  } catch (const std::exception& e) {
    fail(e.what());
  } catch (...) {
    fail("unknown exception");
  }
  return false;
}

bool Tracker::gauss_newton_diagonal(const Vector& z, Vector& out) {
  try {
    return functional_.gauss_newton_diagonal(z, out) && out.size() == n_ && out.allFinite() && out.minCoeff() > 0.0;
  } catch (const EvaluationError&) {
  } catch (const std::exception& e) {
    fail(e.what());
  } catch (...) {
    fail("unknown exception");
  }
  return false;
}

bool Tracker::gradient_difference(const Vector& z, const Vector& g, const Vector& v, Vector& out) {
  const double v_norm = v.lpNorm<Eigen::Infinity>();
  if (v_norm == 0.0) {
    out = Vector::Zero(n_);
    return true;
  }
  const double h = 1e-6 * (1.0 + z.lpNorm<Eigen::Infinity>()) / v_norm;
  try {
    Vector shifted;
    const double f = functional_.value_and_gradient(z + h * v, shifted);
    out = (shifted - g) / h;
    return std::isfinite(f) && out.size() == n_ && out.allFinite();
  } catch (const EvaluationError&) {
  } catch (const std::exception& e) {
    fail(e.what());
  } catch (...) {
    fail("unknown exception");
  }
  return false;
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
  if (skip_resumed_row_) {  // the back-end's row 0 at the checkpoint's iterate: already there
    skip_resumed_row_ = false;
    if (z == last_row_z_) return;
  }
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
  // Solves of this run (and of the run it resumes), not the functional's earlier work.
  const FunctionalCounters work = counters();
  row.forward_solves = work.forward_solves;
  row.adjoint_solves = work.adjoint_solves;
  history_.push_back(row);
  last_row_z_ = z;
  print_row(row);
  if (options_.checkpoint_every > 0 && row.iteration > 0 && row.iteration % options_.checkpoint_every == 0)
    checkpoint();
}

void Tracker::checkpoint() {
  if (!options_.on_checkpoint || history_.empty() || checkpoint_failed_) return;
  OptimizerCheckpoint c;
  c.backend = options_.backend;
  c.iteration = history_.back().iteration;
  c.z = last_row_z_;
  c.objective = history_.back().objective;
  if (has_best_) {
    c.best_z = best_z_;
    c.best_objective = best_f_;
    c.best_violation = best_violation_;
  }
  c.history = history_;
  c.evaluations = evaluations_;
  c.failed_evaluations = failed_evaluations_;
  c.seconds = seconds();
  c.counters = counters();
  c.backend_state = backend_state_;
  last_checkpoint_ = c.iteration;
  // Called from inside the back-ends' callbacks: nothing may escape.
  try {
    options_.on_checkpoint(c);
  } catch (const std::exception& e) {
    checkpoint_failed_ = true;
    request_stop(OptimizerStatus::failed, std::string("checkpoint failed: ") + e.what());
  } catch (...) {
    checkpoint_failed_ = true;
    request_stop(OptimizerStatus::failed, "checkpoint failed");
  }
}

void Tracker::final_checkpoint() {
  if (!history_.empty() && history_.back().iteration != last_checkpoint_) checkpoint();
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

}  // namespace tailor::detail
