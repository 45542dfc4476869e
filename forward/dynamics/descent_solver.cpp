#include "forward/dynamics/descent_solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "forward/core/format_number.hpp"
#include "forward/core/timing.hpp"

namespace tailor {

std::string to_string(DescentStatus status) {
  switch (status) {
    case DescentStatus::converged:
      return "converged";
    case DescentStatus::iteration_budget:
      return "iteration_budget";
    case DescentStatus::stalled:
      return "stalled";
    case DescentStatus::non_finite:
      return "non_finite";
  }
  return "unknown";
}

DescentSolver::DescentSolver(const Model& model, DescentOptions options)
    : options_(std::move(options)), pass_(model, options_.block_size) {
  if (!(options_.step_length >= 0.0)) throw std::invalid_argument("descent: the step length must be >= 0");
  if (options_.power_iterations < 1) throw std::invalid_argument("descent: power_iterations must be >= 1");
  if (options_.rho && !(*options_.rho >= 0.0 && *options_.rho < 1.0))
    throw std::invalid_argument("descent: rho must be in [0, 1)");
  if (options_.rho_estimation_iterations < 2)
    throw std::invalid_argument("descent: rho_estimation_iterations must be >= 2");
  if (options_.max_iterations < 0) throw std::invalid_argument("descent: max_iterations must be >= 0");
}

std::optional<double> DescentSolver::spectral_radius() const { return options_.rho ? options_.rho : estimated_rho_; }

double DescentSolver::automatic_step_length(const Vector& p, const Vector& y) {
  // Power iteration on D^-1 H (similar to the symmetric D^-1/2 H D^-1/2, so its eigenvalues
  // are real), H the exact reduced Hessian at y, D^-1 from the pass at y (current_), from a
  // fixed pseudo-random start: v <- D^-1 H v / ||D^-1 H v||, lambda ~ ||D^-1 H v|| / ||v||.
  const Model& model = pass_.model();
  const Vector x = model.state(y, p);
  const int m = static_cast<int>(y.size());
  Vector v(m), Hv, DinvHv;
  std::uint64_t seed = 0x9E3779B97F4A7C15ull;
  for (int i = 0; i < m; ++i) {  // a fixed xorshift sequence in [-1, 1]
    seed ^= seed << 13, seed ^= seed >> 7, seed ^= seed << 17;
    v[i] = static_cast<double>(seed >> 11) / 4503599627370496.0 - 1.0;
  }
  double lambda = 0.0;
  for (int k = 0; k < options_.power_iterations; ++k) {
    Hv = model.elimination().reduce(model.hessian_times(x, p, model.elimination().expand_direction(v)));
    pass_.apply_inverse(current_, Hv, DinvHv);
    const double norm = DinvHv.norm();
    if (!(norm > 0.0) || !std::isfinite(norm)) break;
    lambda = norm / v.norm();
    v = DinvHv / norm;
  }
  return lambda > 0.0 ? options_.step_length_factor / lambda : 1.0;
}

DescentResult DescentSolver::solve(const Vector& p, Vector& y) {
  const auto t0 = Clock::now();
  const Model& model = pass_.model();
  DescentResult r;
  pass_.evaluate(y, p, current_, true);
  double residual = current_.gradient.norm();
  r.initial_energy = r.final_energy = current_.energy;
  r.initial_residual = r.final_residual = residual;
  r.scale = std::max(residual, options_.reference_residual);
  const double target = std::max(options_.relative_tolerance * r.scale, options_.absolute_tolerance);
  auto finish = [&](DescentStatus status, std::string message) {
    r.status = status;
    r.message = std::move(message) + ": ||g|| " + format_number(r.final_residual, "%.3e") + " (" +
                format_number(r.scale > 0 ? r.final_residual / r.scale : 0.0, "%.2e") + " of the scale) after " +
                std::to_string(r.iterations) + " iterations, " + std::to_string(r.rejections) + " rejected";
    r.rho = spectral_radius().value_or(0.0);
    r.seconds = seconds_since(t0);
    return r;
  };
  if (!std::isfinite(current_.energy) || !std::isfinite(residual))
    return finish(DescentStatus::non_finite, "the start's energy or gradient is not finite");
  if (residual <= target) return finish(DescentStatus::converged, "converged at the start");

  if (!start_alpha_) start_alpha_ = options_.step_length > 0.0 ? options_.step_length : automatic_step_length(p, y);
  bool estimating = !spectral_radius().has_value();
  double rho = spectral_radius().value_or(0.0);
  double alpha = *start_alpha_;
  const double alpha_start = alpha;
  const int window_length = options_.rho_estimation_iterations;
  std::vector<double> window{residual};  // residuals of the accepted plain iterations at one alpha
  Vector previous = y, direction, trial_y;
  double omega = 1.0;
  int since_restart = 0;
  while (r.iterations < options_.max_iterations) {
    pass_.apply_inverse(current_, current_.gradient, direction);
    double omega_next = 1.0;
    if (!estimating && rho > 0.0)
      omega_next = since_restart == 0   ? 1.0
                   : since_restart == 1 ? 2.0 / (2.0 - rho * rho)
                                        : 4.0 / (4.0 - rho * rho * omega);
    trial_y = omega_next * (y - alpha * direction - previous) + previous;
    // Terms that bound a step (CCD) reject a trial point they would clip.
    const bool admissible =
        model.max_step(model.state(y, p), model.elimination().expand_direction(trial_y - y)) >= 1.0;
    pass_.evaluate(trial_y, p, trial_, true);
    ++r.iterations;
    const double trial_residual = trial_.gradient.norm();
    const bool finite = std::isfinite(trial_.energy) && std::isfinite(trial_residual);
    // No rise. Within the energy's round-off, where comparing energies says nothing (near the
    // minimum its changes fall below it long before the residual reaches Newton's
    // tolerances), the change is taken from the gradients, which keep their relative
    // precision: E(u') - E(u) = (g(u) + g(u'))^T (u' - u) / 2 + O(|u' - u|^3) (trapezoidal rule).
    const double roundoff = std::max(current_.energy_roundoff, trial_.energy_roundoff);
    const bool decrease =
        admissible && finite &&
        (trial_.energy <= current_.energy - roundoff ||
         (trial_.energy <= current_.energy + roundoff &&
          0.5 * (current_.gradient + trial_.gradient).dot(trial_y - y) <= 0.0));
    if (options_.keep_history) r.history.push_back({trial_.energy, trial_residual, alpha, omega_next, decrease});
    if (!finite && !options_.energy_check) return finish(DescentStatus::non_finite, "a trial point is not finite");
    if (options_.energy_check && !decrease) {
      // Simplified Wolfe rule: halve the step, restart the acceleration from the current point.
      ++r.rejections;
      alpha *= 0.5;
      omega = 1.0, since_restart = 0;
      previous = y;
      window.assign(1, residual);
      if (alpha < options_.min_step_length * alpha_start)
        return finish(DescentStatus::stalled, "no decrease of the energy at the smallest step");
      continue;
    }
    previous.swap(y);
    y.swap(trial_y);
    std::swap(current_, trial_);
    omega = omega_next, ++since_restart;
    residual = trial_residual;
    r.final_energy = current_.energy, r.final_residual = residual;
    if (residual <= target) return finish(DescentStatus::converged, "converged");
    if (estimating) {
      window.push_back(residual);
      if (static_cast<int>(window.size()) > window_length) {
        const int half = window_length / 2;
        const double ratio = window[static_cast<std::size_t>(window_length)] / window[static_cast<std::size_t>(half)];
        const double estimate = std::pow(ratio, 1.0 / (window_length - half));
        estimated_rho_ = std::clamp(std::isfinite(estimate) ? estimate : 0.0, 0.0, options_.rho_max);
        start_alpha_ = alpha;  // the estimate belongs to this alpha
        estimating = false;
        rho = *estimated_rho_;
        omega = 1.0, since_restart = 0;
        previous = y;
      }
    }
  }
  return finish(DescentStatus::iteration_budget, "iteration budget spent");
}

}  // namespace tailor
