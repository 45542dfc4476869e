#pragma once
// RigidContactTerm: the IPC barrier (forward/contact/contact_potential.hpp) between rigid
// bodies, as an EnergyTerm over the body DOFs q_b = (T_b, w_b) (rigid IPC, Ferguson et al.
// 2021). By the chain rule through x = T_b + R(w_b) V (rigid_body_system.hpp), per active
// pair with stencil Jacobian J = dx/dq (12 x 6 per body involved):
//   dB/dq = J^T dB/dx,
//   d2B/dq2 = J^T (d2B/dx2) J + sum_k sum_i (dB/dx_k)_i d2(x_k)_i/dw dw   (the second
//   derivative of R, rotation.hpp; it acts on the rotation block of each vertex's body).
// In projected mode the per-pair 12 x 12 (or 24 x 24) matrix in q is projected to PSD.
//
// Hessian pattern: the dense coupling of all bodies' DOFs ((6 B)^2 slots), exact for any
// motion; fine for tens of bodies.
//
// max_step(): additive CCD on the curved trajectories q + t dq, t in [0, 1], with the rate
// bound |dx/dt| <= |dT_b| + |dw_b| |V| (the rotation's left Jacobian has norm <= 1), so no
// contact is missed between the straight motion's samples (no linearization of rotations).
#include "forward/contact/contact_potential.hpp"
#include "forward/contact/slot_map.hpp"
#include "forward/core/energy_term.hpp"
#include "forward/rigid/rigid_body_system.hpp"

namespace tailor::rigid {

class RigidContactTerm final : public EnergyTerm {
 public:
  // `system` must outlive the term.
  RigidContactTerm(const RigidBodySystem& system, contact::ContactOptions options);

  std::string name() const override { return "rigid_contact"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;
  double max_step(const Vector& x, const Vector& dx) const override;

  const contact::ContactPotential& potential() const { return potential_; }
  contact::ContactPotential& potential() { return potential_; }
  // Smallest distance between bodies within `range` at state q (infinity if none).
  double min_distance(const Vector& q, double range) const;

 private:
  const RigidBodySystem& system_;
  contact::ContactPotential potential_;
  contact::SlotMap slots_;
};

}  // namespace tailor::rigid
