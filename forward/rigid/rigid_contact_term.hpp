#pragma once
// RigidContactTerm: the IPC barrier (forward/contact/contact_potential.hpp) between rigid
// bodies and deformable surfaces (contact_bodies.hpp), as an EnergyTerm over the model's DOFs
// (rigid IPC, Ferguson et al. 2021). By the chain rule through x(q) (ContactBodies::add_stencil),
// per active pair with stencil Jacobian J = dx/dq:
//   dB/dq = J^T dB/dx,
//   d2B/dq2 = J^T (d2B/dx2) J + sum_k sum_i (dB/dx_k)_i d2(x_k)_i/dw dw   (the second
//   derivative of R, rotation.hpp; it acts on the rotation block of each rigid vertex's body).
// In projected mode the per-pair matrix in q is projected to PSD.
//
// Hessian pattern: ContactBodies::add_pattern (dense over the rigid DOFs, exact for any motion;
// fine for tens of bodies).
//
// max_step(): additive CCD on the curved trajectories q + t dq, t in [0, 1], with the rate
// bound |dx/dt| <= |dT_b| + |dw_b| |V| (the rotation's left Jacobian has norm <= 1), so no
// contact is missed between the straight motion's samples (no linearization of rotations).
#include <memory>

#include "forward/contact/contact_potential.hpp"
#include "forward/contact/slot_map.hpp"
#include "forward/core/energy_term.hpp"
#include "forward/rigid/contact_bodies.hpp"

namespace tailor::rigid {

class RigidContactTerm final : public EnergyTerm {
 public:
  // Rigid bodies only; `system` must outlive the term.
  RigidContactTerm(const RigidBodySystem& system, contact::ContactOptions options);
  // Rigid bodies and deformable surfaces; `rest_state` (size bodies->num_dofs()) gives the rest
  // edge lengths of the mollifier.
  RigidContactTerm(std::shared_ptr<const ContactBodies> bodies, const Vector& rest_state,
                   contact::ContactOptions options);

  std::string name() const override { return "rigid_contact"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;
  double max_step(const Vector& x, const Vector& dx) const override;

  const contact::ContactPotential& potential() const { return potential_; }
  contact::ContactPotential& potential() { return potential_; }
  const ContactBodies& bodies() const { return *bodies_; }
  std::shared_ptr<const ContactBodies> shared_bodies() const { return bodies_; }
  const contact::SlotMap& slots() const { return slots_; }
  // Smallest distance between bodies within `range` at state q (infinity if none).
  double min_distance(const Vector& q, double range) const;
  // Per DOF, the barrier's -dB/dq at kappa = 1 (the barrier's direction for the stiffness balance).
  Vector unit_stiffness_gradient(const Vector& q) const;
  // The contact force on every surface vertex, -dB/dx (one row per surface vertex).
  contact::Positions vertex_forces(const Vector& q) const;

 private:
  std::shared_ptr<const ContactBodies> bodies_;
  contact::ContactPotential potential_;
  contact::SlotMap slots_;
};

}  // namespace tailor::rigid
