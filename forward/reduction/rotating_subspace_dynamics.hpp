#pragma once
// Newmark dynamics in a subspace that turns with the body's domains (docs/reduction.md,
// "Per-domain rotations"): at the start of every step the rotation R_d of each domain is fitted
// to the current displacement (domain_rotations.hpp), the step's basis is B = Rbar(u_n) Phi
// (each vertex's columns carried by the weighted blend of its domains' rotations) and the step
// u_{n+1} = u_n + B dq minimizes the full-space Newmark incremental potential over dq:
//
//   P(dq) = 2/h^2 |d|_M^2 - d.M(4 v/h + a) + 1/h |d|_C^2 - d.C v + E(x_0 + u_n + d) - f.d,  d = B dq,
//
// whose gradient B^T [M a' + C v' + dE/dx - f] is the Galerkin projection of the full-space
// Newmark residual (a' = 4 (d - h v)/h^2 - a, v' = v + h (a + a')/2; Newmark average
// acceleration) and whose Hessian is B^T (4/h^2 M + 2/h C + K(u_n + d)) B. Rayleigh damping
// C = alpha M + beta K(rest) (full space, as the full-space integrator). Positions, velocities and
// accelerations are kept in full space; at the start of a step v and a are M-projected onto
// span(B) (which drops the part outside the turned subspace; it never adds kinetic energy).
//
// With rotations off (or one domain that does not turn) B = Phi at every step and the scheme is
// ReducedDynamics' Newmark on the projected model (ProjectedReducedModel): the global linear
// basis it is compared with. Every evaluation visits the whole mesh (cost proportional to the
// mesh: the rotated basis changes every step, so no reduced polynomial is precomputed).
// Units: time in s, alpha in 1/s, beta in s; u, v, a full-space (num_dofs), from the rest state.
#include <string>
#include <vector>

#include "forward/core/model.hpp"
#include "forward/mesh/mesh.hpp"
#include "forward/reduction/domain_rotations.hpp"

namespace tailor {

struct RotatingSubspaceOptions {
  double time_step = 1e-2;          // h [s], > 0
  double rayleigh_mass = 0.0;       // alpha [1/s], >= 0
  double rayleigh_stiffness = 0.0;  // beta [s], >= 0
  bool rotations = true;            // false: the fixed basis Phi
  RotationBlend blend = RotationBlend::linear;  // how a vertex's domains' rotations combine
  int max_newton_iterations = 30;
  double newton_tolerance = 1e-10;  // on |gradient| relative to the sizes of its parts
};

struct SubspaceState {
  Vector u, v, a;  // displacement from rest, velocity, acceleration (full space)
};

class RotatingSubspaceDynamics {
 public:
  // elastic: the materials (energy E(x), its gradient and exact Hessian), referenced; rest: its
  // rest state; mass: full-space mass matrix; external_force: constant full-space load (gravity
  // M g included); basis: num_dofs x r, zero on the supports; weights: num_vertices x domains
  // (rows sum to 1; domain_vertex_weights or OverlappingDomains::weights). 3D meshes. Throws
  // std::invalid_argument on bad sizes or options.
  RotatingSubspaceDynamics(const Model& elastic, const Mesh& mesh, Vector p, Vector rest, SparseMatrix mass,
                           Vector external_force, Matrix basis, Matrix weights, RotatingSubspaceOptions options);

  int size() const { return static_cast<int>(basis_.cols()); }
  const RotatingSubspaceOptions& options() const { return options_; }

  // At rest (u = 0) with initial velocity v0 (projected onto span(Phi)); a_0 from the projected
  // equation of motion B^T (M a_0 + C v_0 - f) = 0.
  SubspaceState initial_state(const Vector& v0) const;
  // The step basis at displacement u: Rbar(u) Phi (Phi with rotations off).
  Matrix step_basis(const Vector& u) const;
  // One step; false (with a message) when Newton does not converge or the state is not finite.
  bool step(const SubspaceState& current, SubspaceState& next, int& iterations, std::string& message) const;
  // P(dq) of a step from `current` in basis B (value, gradient, Hessian; null: not requested).
  // current.v and current.a as given (step() projects them first).
  void step_potential(const SubspaceState& current, const Matrix& B, const Vector& dq, double* value,
                      Vector* gradient, Matrix* hessian) const;
  // 1/2 v.M v + E(x_0 + u) - f.u (0 at rest; with Rayleigh damping it must not rise).
  double total_energy(const SubspaceState& state) const;
  // The smallest element volume ratio det(F) at displacement u (< 0: an element is inverted).
  double smallest_volume_ratio(const Vector& u) const;

 private:
  Matrix stiffness_times(const Vector& x, HessianMode mode, const Matrix& B) const;  // (d2E/dx2) B
  Matrix damping_times(const Matrix& B) const;                                       // C B
  std::vector<SparseMatrix> rest_hessians_;                                          // per term, for C
  const Model& elastic_;
  const Mesh& mesh_;
  Vector p_, rest_;
  SparseMatrix mass_;
  Vector external_force_, vertex_mass_;
  Matrix basis_, weights_;
  RotatingSubspaceOptions options_;
};

}  // namespace tailor
