#pragma once
// Derivative checks for energy terms (and anything else shaped like one): analytic
// derivatives against central differences along random directions, with the error tabulated
// over a sequence of step halvings and its observed convergence order.
//
// Checks, for a term E(x, p) at (x, p):
//   gradient        dE/dx . d          vs (E(x+hd) - E(x-hd)) / 2h
//   hessian         H d                vs (g(x+hd) - g(x-hd)) / 2h
//   param_gradient  dE/dp . q          vs (E(p+hq) - E(p-hq)) / 2h
//   mixed           (d2E/dxdp) q       vs (g(p+hq) - g(p-hq)) / 2h
//   mixed_transpose ((d2E/dxdp)^T w).q vs (w.g(p+hq) - w.g(p-hq)) / 2h
// A check passes when the best relative error is below `tolerance`, or when the error falls
// at second order over at least three step halvings and is below sqrt(tolerance). It fails, with a message,
// when the analytic quantity vanishes while the differences do not, and it is reported as
// "vanishing" (not passed) when both vanish: a check must not pass by accident.
#include <functional>
#include <string>
#include <vector>

#include "forward/core/energy_term.hpp"

namespace tailor {

struct DerivativeCheckOptions {
  // Directions: d_i = scale_x * u_i, q_i = max(|p_i|, parameter_floor) * u_i, u_i uniform in
  // [-1, 1]; scale_x = max(1, ||x||_inf) unless state_scale > 0.
  double state_scale = 0.0;
  double parameter_floor = 1e-8;
  double initial_step = 1e-3;  // h_0 (relative, multiplies the direction)
  int halvings = 6;            // steps h_0, h_0/2, ..., h_0/2^halvings
  double tolerance = 1e-6;     // on the best relative error
  unsigned seed = 1;
  HessianMode hessian_mode = HessianMode::exact;
  // Restrict parameter perturbations to these indices (empty: all).
  std::vector<int> parameter_indices;
};

struct StepError {
  double step;
  double error;  // |difference - analytic| / |analytic|
  double rate;   // log2(previous error / error); NaN for the first row
};

struct DerivativeCheck {
  std::string quantity;      // "gradient", "hessian", "param_gradient", "mixed"
  double analytic_norm = 0;  // |analytic| along the direction
  double best_error = 0;     // smallest relative error over the steps
  double observed_order = 0; // median rate over rows above the round-off floor (NaN if none)
  bool passed = false;
  // Both the analytic derivative and the differences vanish along the direction: nothing was
  // tested (e.g. the Hessian of a term linear in x). Never counted as passed.
  bool vanishing = false;
  std::string message;
  std::vector<StepError> steps;
};

struct EnergyTermCheck {
  std::string term;
  std::vector<DerivativeCheck> checks;
  bool passed() const;
  std::string table() const;  // printable convergence table
};

// Runs every applicable check (mixed and param_gradient only when p is non-empty).
EnergyTermCheck check_energy_term(const EnergyTerm& term, const Vector& x, const Vector& p,
                                  const DerivativeCheckOptions& options = {});

// Generic building block: compares an analytic directional derivative `analytic` of a
// vector-valued function against central differences of `function` along a step parameter t.
// Used for gradients (size-1 vectors) as well as Hessian-vector and mixed products.
DerivativeCheck check_directional_derivative(const std::string& quantity,
                                             const std::function<Vector(double)>& function,
                                             const Vector& analytic, const DerivativeCheckOptions& options);

}  // namespace tailor
