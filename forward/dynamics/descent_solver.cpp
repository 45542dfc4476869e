#include "forward/dynamics/descent_solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "forward/core/format_number.hpp"
#include "forward/core/timing.hpp"
#include "forward/dynamics/descent_device.hpp"
#include "forward/dynamics/descent_vertex_blocks.hpp"

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

std::string to_string(DescentDevice device) {
  switch (device) {
    case DescentDevice::cpu:
      return "cpu";
    case DescentDevice::gpu:
      return "gpu";
    case DescentDevice::automatic:
      return "auto";
  }
  return "unknown";
}

DescentSolver::DescentSolver(const Model& model, DescentOptions options) : options_(std::move(options)) {
  if (!(options_.step_length >= 0.0)) throw std::invalid_argument("descent: the step length must be >= 0");
  if (options_.power_iterations < 1) throw std::invalid_argument("descent: power_iterations must be >= 1");
  if (options_.rho && !(*options_.rho >= 0.0 && *options_.rho < 1.0))
    throw std::invalid_argument("descent: rho must be in [0, 1)");
  if (options_.rho_estimation_iterations < 2)
    throw std::invalid_argument("descent: rho_estimation_iterations must be >= 2");
  if (options_.max_iterations < 0) throw std::invalid_argument("descent: max_iterations must be >= 0");
  const bool device = options_.device == DescentDevice::gpu ||
                      (options_.device == DescentDevice::automatic && cuda_device_usable() &&
                       VertexBlockModel::check(model).empty() && options_.block_size == 3);
  if (device)
    backend_ = make_device_backend(model);
  else if (options_.preconditioner == DescentPreconditioner::vertex_blocks)
    backend_ = vertex_block_host_backend(model);
  else
    backend_ = projected_hessian_backend(model, options_.block_size);
}

std::optional<double> DescentSolver::spectral_radius() const { return options_.rho ? options_.rho : estimated_rho_; }

BlockJacobiPass& DescentSolver::pass() {
  BlockJacobiPass* pass = backend_->projected_pass();
  if (!pass) throw std::logic_error("descent: the solver runs the vertex-block rule or on the device: no BlockJacobiPass");
  return *pass;
}

DescentResult DescentSolver::solve(const Vector& p, Vector& y) {
  const auto t0 = Clock::now();
  DescentBackend& backend = *backend_;
  DescentResult r;
  DescentBackend::Point current = backend.start(p, y);
  double residual = current.residual;
  r.initial_energy = r.final_energy = current.energy;
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
  if (!std::isfinite(current.energy) || !std::isfinite(residual))
    return finish(DescentStatus::non_finite, "the start's energy or gradient is not finite");
  if (residual <= target) return finish(DescentStatus::converged, "converged at the start");

  if (!start_alpha_) {
    // Automatic: step_length_factor / lambda_max(D^-1 H) (plain descent is stable below 2 /
    // lambda_max; the power method approaches lambda_max from below, so the factor keeps a margin).
    const double lambda = options_.step_length > 0.0 ? 0.0 : backend.largest_eigenvalue(options_.power_iterations);
    start_alpha_ = options_.step_length > 0.0 ? options_.step_length
                   : lambda > 0.0                ? options_.step_length_factor / lambda
                                                 : 1.0;
  }
  bool estimating = !spectral_radius().has_value();
  double rho = spectral_radius().value_or(0.0);
  double alpha = *start_alpha_;
  const double alpha_start = alpha;
  const int window_length = options_.rho_estimation_iterations;
  std::vector<double> window{residual};  // residuals of the accepted plain iterations at one alpha
  double omega = 1.0;
  int since_restart = 0;
  while (r.iterations < options_.max_iterations) {
    double omega_next = 1.0;
    if (!estimating && rho > 0.0)
      omega_next = since_restart == 0   ? 1.0
                   : since_restart == 1 ? 2.0 / (2.0 - rho * rho)
                                        : 4.0 / (4.0 - rho * rho * omega);
    bool admissible = true;
    const DescentBackend::Point trial = backend.try_step(alpha, omega_next, admissible);
    ++r.iterations;
    const double trial_residual = trial.residual;
    const bool finite = std::isfinite(trial.energy) && std::isfinite(trial_residual);
    // No rise. Within the energy's round-off, where comparing energies says nothing (near the
    // minimum its changes fall below it long before the residual reaches Newton's
    // tolerances), the change is taken from the gradients, which keep their relative
    // precision: E(u') - E(u) = (g(u) + g(u'))^T (u' - u) / 2 + O(|u' - u|^3) (trapezoidal rule).
    const double roundoff = std::max(current.energy_roundoff, trial.energy_roundoff);
    const bool decrease = admissible && finite &&
                          (trial.energy <= current.energy - roundoff ||
                           (trial.energy <= current.energy + roundoff && backend.trapezoid_change() <= 0.0));
    if (options_.keep_history) r.history.push_back({trial.energy, trial_residual, alpha, omega_next, decrease});
    if (!finite && !options_.energy_check) {
      backend.read(y);
      return finish(DescentStatus::non_finite, "a trial point is not finite");
    }
    if (options_.energy_check && !decrease) {
      // Simplified Wolfe rule: halve the step, restart the acceleration from the current point.
      ++r.rejections;
      alpha *= 0.5;
      omega = 1.0, since_restart = 0;
      backend.restart();
      window.assign(1, residual);
      if (alpha < options_.min_step_length * alpha_start) {
        backend.read(y);
        return finish(DescentStatus::stalled, "no decrease of the energy at the smallest step");
      }
      continue;
    }
    backend.accept();
    current = trial;
    omega = omega_next, ++since_restart;
    residual = trial_residual;
    r.final_energy = current.energy, r.final_residual = residual;
    if (residual <= target) {
      backend.read(y);
      return finish(DescentStatus::converged, "converged");
    }
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
        backend.restart();
      }
    }
  }
  backend.read(y);
  return finish(DescentStatus::iteration_budget, "iteration budget spent");
}

}  // namespace tailor
