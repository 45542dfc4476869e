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

  // The dissipation interface, in the velocity v.
  // request.value += D(v); request.gradient += dD/dv; request.hessian_values = d2D/dv2 on the pattern.
  virtual void evaluate_dissipation(const Vector& v, const Vector& p, const EnergyRequest& request) const = 0;
  virtual void dissipation_pattern(HessianPattern& pattern) const = 0;
  virtual void add_dissipation_param_gradient(const Vector& v, const Vector& p,
                                              Vector& gradient_p) const = 0;  // += dD/dp
  // gradient_p += (d2D/dvdp)^T w.
  virtual void add_dissipation_mixed_transpose_times(const Vector& v, const Vector& p, const Vector& w,
                                                     Vector& gradient_p) const = 0;
  // Triplets (dof, parameter) of d2D/dvdp. Default: column by column through the transpose product.
  virtual void add_dissipation_mixed(const Vector& v, const Vector& p, Triplets& mixed) const;

 private:
  std::size_t pattern_size() const;
  double kappa_ = 1.0;
  Vector base_;
  mutable std::size_t pattern_size_ = 0;
  mutable bool pattern_known_ = false;
};

}  // namespace tailor
