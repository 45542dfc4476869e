#pragma once
// The inertia part of one implicit time step's incremental potential (docs/methods.md section 1):
//   E(x) = c/2 (x - x~)^T M(rho) (x - x~) - g^T (x - x~),
// c [1/time^2] the scheme's inertia coefficient (1/h^2 for implicit Euler), x~ the predictor
// (positions), g an optional force carried over from the previous step (the trapezoidal
// rule's M a_n; empty = none). Its gradient c M (x - x~) - g is M times the scheme's
// acceleration minus g. (g^T x~ is subtracted, a constant, so that E stays small near the
// solution: Newton's line search compares energies and a large offset would drown them.) The time integrator
// sets (c, x~, g) before each step; parameters: the per-element density of the mass operator.
#include <bit>
#include <cstdint>
#include <memory>

#include "forward/core/energy_term.hpp"
#include "forward/dynamics/mass_operator.hpp"

namespace tailor {

class InertiaTerm final : public EnergyTerm {
 public:
  explicit InertiaTerm(std::shared_ptr<const MassOperator> mass);

  std::string name() const override { return "inertia"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override { mass_->hessian_pattern(pattern); }
  // c M(rho): constant in x. The revision is c's bit pattern: a return to an earlier c
  // (Newmark's start evaluates g_0 with c = 0) finds the factorization kept for it.
  bool hessian_is_constant() const override { return true; }
  std::uint64_t hessian_revision() const override { return std::bit_cast<std::uint64_t>(coefficient_); }
  // out += c M w, by the mass operator (no Hessian values on the pattern).
  void add_hessian_times(const Vector& x, const Vector& p, const Vector& w, Vector& out,
                         HessianMode mode = HessianMode::exact) const override;
  void add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const override;
  void add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const override;
  void add_mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w,
                                 Vector& gradient_p) const override;

  // c >= 0; predictor of size num_dofs; carried_force empty or of size num_dofs.
  void set_step(double coefficient, Vector predictor, Vector carried_force = Vector());
  double coefficient() const { return coefficient_; }
  const Vector& predictor() const { return predictor_; }
  const Vector& carried_force() const { return carried_force_; }
  const MassOperator& mass() const { return *mass_; }
  std::shared_ptr<const MassOperator> mass_ptr() const { return mass_; }

 private:
  std::shared_ptr<const MassOperator> mass_;
  double coefficient_ = 0.0;
  Vector predictor_, carried_force_;
};

}  // namespace tailor
