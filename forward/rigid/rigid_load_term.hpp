#pragma once
// Constant generalized loads on rigid body DOFs: E(q) = - f . (q - q0) [energy], with f the
// force on each translation [force] and a generalized moment on each rotation vector
// [force length] (equal to the torque for rotations about a fixed axis through w = 0 only).
#include "forward/core/energy_term.hpp"

namespace tailor::rigid {

class RigidLoadTerm final : public EnergyTerm {
 public:
  // `loads` and `reference` (q0) have one entry per DOF; throws on mismatched sizes.
  RigidLoadTerm(Vector loads, Vector reference);
  std::string name() const override { return "rigid_load"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void set_loads(Vector loads);

 private:
  Vector loads_, reference_;
};

}  // namespace tailor::rigid
