#pragma once
// DampingTerm: a damping model given by a dissipation potential D(v, p) in the velocity v
// [length / time] (Rayleigh's dissipation function; the damping force is -dD/dv). A time step
// of an implicit scheme expresses the new velocity as an affine function of the new positions,
//   v(x) = (x - x^) / kappa,
// (implicit Euler: kappa = h, x^ = x_n; the trapezoidal rule: kappa = h/2, x^ = x_n + h/2 v_n;
// BDF2: kappa = 2h/3, x^ = (4 x_n - x_{n-1}) / 3), and the term adds kappa D(v(x), p) to the
// incremental potential: its gradient in x is dD/dv, the damping force's reaction, so the
// step's optimality condition is the discrete equation of motion with the damping force at
// v_{n+1}. Because the term depends on x and x^ only through x - x^, its derivative in x^ is
// minus its derivative in x (the adjoint uses this).
//
// A damping model implements the dissipation interface below (D, dD/dv, d2D/dv2 on a fixed
// pattern, dD/dp, d2D/dvdp); it must be convex in v and have D >= 0 (dissipative).
// RayleighDamping is the first model; example-based damping plugs in the same way.
#include <bit>
#include <cstdint>

#include "forward/core/energy_term.hpp"

namespace tailor {

class DampingTerm : public EnergyTerm {
 public:
  // v(x) = (x - base) / velocity_scale; velocity_scale > 0 [time].
  void set_velocity_map(double velocity_scale, Vector base);
  double velocity_scale() const { return kappa_; }
  const Vector& velocity_base() const { return base_; }
  Vector velocity(const Vector& x) const;

  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const final;
  void hessian_pattern(HessianPattern& pattern) const final { dissipation_pattern(pattern); }
  void add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const final;
  void add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const final;
  void add_mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w,
                                 Vector& gradient_p) const final;
  void add_low_rank_hessian(const Vector& x, const Vector& p, LowRankHessian& update,
                            HessianMode mode = HessianMode::exact) const final;
  // out += (d2D/dv2) w / kappa (exact and projected coincide), low-rank part included: through
  // add_dissipation_hessian_times where the model has it, else by the Hessian values on the
  // pattern (EnergyTerm's default, an element loop and the pattern per call).
  void add_hessian_times(const Vector& x, const Vector& p, const Vector& w, Vector& out,
                         HessianMode mode = HessianMode::exact) const final;
  // A quadratic dissipation gives the constant Hessian (d2D/dv2) / kappa. Its revision is
  // kappa's bit pattern: a return to an earlier kappa (Newmark's start evaluates g_0 with
  // kappa = h, its steps use h/2) finds the factorization kept for it.
  bool hessian_is_constant() const final { return dissipation_is_quadratic(); }
  std::uint64_t hessian_revision() const final { return std::bit_cast<std::uint64_t>(kappa_); }

  // True when D is quadratic in v with coefficients that depend on p only (Rayleigh).
  virtual bool dissipation_is_quadratic() const { return false; }

  // The dissipation interface, in the velocity v.
  // request.value += D(v); request.gradient += dD/dv; request.hessian_values = d2D/dv2 on the pattern.
  virtual void evaluate_dissipation(const Vector& v, const Vector& p, const EnergyRequest& request) const = 0;
  virtual void dissipation_pattern(HessianPattern& pattern) const = 0;
  virtual void add_dissipation_param_gradient(const Vector& v, const Vector& p,
                                              Vector& gradient_p) const = 0;  // += dD/dp
  // gradient_p += (d2D/dvdp)^T w.
  virtual void add_dissipation_mixed_transpose_times(const Vector& v, const Vector& p, const Vector& w,
                                                     Vector& gradient_p) const = 0;
  // out += (d2D/dv2) w, the part on the pattern (without the low-rank part). Returns false when
  // the model has no such product (the default), and the caller goes through the pattern.
  virtual bool add_dissipation_hessian_times(const Vector& v, const Vector& p, const Vector& w,
                                             Vector& out) const {
    (void)v, (void)p, (void)w, (void)out;
    return false;
  }
  // Triplets (dof, parameter) of d2D/dvdp. Default: column by column through the transpose product.
  virtual void add_dissipation_mixed(const Vector& v, const Vector& p, Triplets& mixed) const;
  // The low-rank part of d2D/dv2 kept off the pattern (see LowRankHessian). Default: none.
  virtual void add_dissipation_low_rank_hessian(const Vector& v, const Vector& p,
                                                LowRankHessian& update) const {
    (void)v, (void)p, (void)update;
  }
  // Called by the time integrator with the state (x_n, v_n) at the start of each step, before
  // the step's solve: models whose coefficients depend on the state lag them here, which keeps
  // the step's potential convex in x_{n+1}. Default: nothing.
  virtual void set_step_start(const Vector& x, const Vector& v) { (void)x, (void)v; }
  // For such models: x_start_bar += (d(w^T dD/dv)/dx_n), v_start_bar += (d(w^T dD/dv)/dv_n) at x
  // (v = velocity(x)) and the (x_n, v_n) last given to set_step_start (the adjoint's history
  // term through the lagged coefficients). Default: no dependence.
  virtual void add_step_start_transpose_times(const Vector& x, const Vector& p, const Vector& w,
                                              Vector& x_start_bar, Vector& v_start_bar) const {
    (void)x, (void)p, (void)w, (void)x_start_bar, (void)v_start_bar;
  }

 private:
  std::size_t pattern_size() const;
  double kappa_ = 1.0;
  Vector base_;
  mutable std::size_t pattern_size_ = 0;
  mutable bool pattern_known_ = false;
};

}  // namespace tailor
