#pragma once
// ContactBodies: the surfaces that take part in contact and how their vertices follow the
// model's DOFs q:
//   rigid body b (rigid_body_system.hpp):  x = T_b + R(w_b) V,  DOFs 6b .. 6b+5;
//   deformable surface vertex v:           x = q[dof_v .. dof_v + 2]  (e.g. the boundary of an
//                                          FEM mesh whose vertex DOFs follow the rigid ones).
// All surfaces form one ContactSurface: rigid surface vertices first (in the system's order),
// then each deformable surface's vertices. Groups: one per rigid body (fixed bodies share one,
// they never meet) and one per deformable surface (no self-contact).
//
// The chain rule for any function f of a pair's stencil of four surface vertices (the
// barrier, the friction potential), with J = dx/dq on the stencil:
//   df/dq = J^T df/dx,   d2f/dq2 = J^T (d2f/dx2) J + sum_k (df/dx_k) . d2(x_k)/dw dw,
// the last sum only for rigid vertices (the second derivative of R, rotation.hpp).
//
// Hessian pattern (contact pairs appear during a solve, the Model's pattern is fixed when the
// solver is built): all rigid DOFs with each other and with every deformable surface DOF, each
// deformable face's (and extra edge's) vertex DOFs with each other, and the surface DOFs of
// different deformable surfaces with each other. Exact for any motion.
#include <array>
#include <string>
#include <vector>

#include "forward/contact/contact_potential.hpp"
#include "forward/contact/slot_map.hpp"
#include "forward/core/energy_term.hpp"
#include "forward/rigid/rigid_body_system.hpp"

namespace tailor::rigid {

struct DeformableSurface {
  std::string name;
  Eigen::MatrixX3i faces;                                 // triangles over the local vertices
  std::vector<int> vertex_dofs;                           // per local vertex: its first DOF (x, y, z)
  Eigen::MatrixX2i extra_edges = Eigen::MatrixX2i(0, 2);  // edges besides the faces' (rods)
};

class ContactBodies {
 public:
  // `num_dofs`: the model's DOFs (default: the rigid system's). Throws std::invalid_argument
  // when a deformable DOF overlaps the rigid DOFs 0 .. 6B-1 or lies past num_dofs.
  explicit ContactBodies(const RigidBodySystem& system, std::vector<DeformableSurface> deformable = {},
                         int num_dofs = -1);

  const RigidBodySystem& rigid() const { return system_; }
  const contact::ContactSurface& surface() const { return surface_; }
  const std::vector<DeformableSurface>& deformable() const { return deformable_; }
  int num_dofs() const { return num_dofs_; }
  // Surface vertex v: its rigid body (>= 0), or -1 for a deformable vertex.
  int body_of(int v) const { return vertex_body_[static_cast<std::size_t>(v)]; }
  // A deformable vertex's first DOF.
  int dof_of(int v) const { return vertex_dof_[static_cast<std::size_t>(v)]; }
  // A rigid vertex's body-frame position V.
  const Eigen::Vector3d& body_frame(int v) const { return body_frame_[static_cast<std::size_t>(v)]; }
  // The first surface vertex of deformable surface i.
  int deformable_offset(int i) const { return deformable_offset_[static_cast<std::size_t>(i)]; }

  // World positions of all surface vertices at state q (size num_dofs()).
  contact::Positions positions(const Vector& q) const;
  // Rotation derivatives of every rigid body at q (for add_stencil).
  std::vector<RotationDerivatives> rotations(const Vector& q) const;
  // The DOF blocks every stencil may couple (see the top of this file).
  void add_pattern(contact::SlotMap& slots) const;

  // Adds a stencil function's gradient `g` and Hessian `H` (12 stencil coordinates: vertex k,
  // axis j -> 3k + j) through x(q) to the request's gradient and to its Hessian values at
  // `slots` (projected to PSD in q in projected mode). `rotations` from rotations(q).
  void add_stencil(const std::array<int, 4>& vertices, const Eigen::Matrix<double, 12, 1>& g,
                   const Eigen::Matrix<double, 12, 12>& H, const std::vector<RotationDerivatives>& rotations,
                   const contact::SlotMap& slots, const EnergyRequest& request) const;
  // Generalized forces of the stencil gradient `g` only (no Hessian).
  void add_stencil_gradient(const std::array<int, 4>& vertices, const Eigen::Matrix<double, 12, 1>& g,
                            const std::vector<RotationDerivatives>& rotations, Vector& gradient) const;

  // Largest safe fraction of the step q -> q + dq for the pairs of `potential` (additive CCD
  // on the exact curved rigid paths T + t dT + R(w + t dw) V and straight deformable ones,
  // with the rate bound |dx/dt| <= |dT| + |dw| |V| (the rotation's left Jacobian has norm
  // <= 1), or |dx| for a deformable vertex).
  double max_step(const Vector& q, const Vector& dq, const contact::ContactPotential& potential) const;

 private:
  const RigidBodySystem& system_;
  std::vector<DeformableSurface> deformable_;
  int num_dofs_;
  contact::ContactSurface surface_;
  std::vector<int> vertex_body_, vertex_dof_, deformable_offset_;
  std::vector<Eigen::Vector3d> body_frame_;
};

}  // namespace tailor::rigid
