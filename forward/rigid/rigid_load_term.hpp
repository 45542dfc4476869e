#pragma once
// Constant loads on rigid bodies: a force f_b on each centre of mass and a torque tau_b (world
// frame) on each body, as
//   E(q) = - sum_b [ f_b . (T_b - T_b^0) + tau_b . theta_b(w_b) ]                    [energy],
//   theta_b(w) = vee( skew( R(w) R_b^T ) ) = 1/2 vee( R(w) R_b^T - R_b R(w)^T ),
// R_b = R(w_b^0) the reference rotation. d theta_b / dw at w = w_b^0 is the rotation's Jacobian
// (the world angular increment per dw: dR R^T = [J dw]), so a torque does the work tau . delta
// theta of a true moment, not tau . delta w. A constant world torque is not conservative in 3D:
// theta_b is exact to first order about the reference, which set_reference() moves to the
// start of each time step (a lagged torque, like lagged friction) or, in statics, to the last
// solution until it no longer changes.
// `loads` has 6 entries per body: (f_b, tau_b). The state may extend past the 6 B body DOFs
// (other DOFs after them are not loaded).
#include <vector>

#include "forward/core/energy_term.hpp"

namespace tailor::rigid {

class RigidLoadTerm final : public EnergyTerm {
 public:
  // `loads` and `reference` (q0) have 6 entries per body; throws on mismatched sizes.
  RigidLoadTerm(Vector loads, Vector reference);
  std::string name() const override { return "rigid_load"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;
  void set_loads(Vector loads);
  const Vector& loads() const { return loads_; }
  // Moves the torques' reference rotations R_b to those of q (translations keep q0).
  void set_reference(const Vector& q);
  bool has_torques() const;

 private:
  Vector loads_, reference_;
  std::vector<Eigen::Matrix3d> reference_rotation_;
};

}  // namespace tailor::rigid
