#pragma once
// Gravity on rigid bodies: E(q, p) = - sum_b m_b g . (T_b - T_b^0) [energy], T_b the centre of
// mass (DOFs 6b..6b+2), T_b^0 its initial value (a constant that keeps E small). With
// mass_offset >= 0 the masses are parameters m_b = p[mass_offset + b]; otherwise the
// bodies' own masses are used and the term has no parameters.
#include "forward/core/energy_term.hpp"
#include "forward/rigid/rigid_body_system.hpp"

namespace tailor::rigid {

class RigidGravityTerm final : public EnergyTerm {
 public:
  RigidGravityTerm(const RigidBodySystem& system, const Eigen::Vector3d& gravity, int mass_offset = -1);
  std::string name() const override { return "rigid_gravity"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const override;
  void add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const override;

 private:
  double mass(const Vector& p, int b) const;
  Eigen::Vector3d gravity_;
  int mass_offset_;
  Vector masses_, initial_;
};

}  // namespace tailor::rigid
