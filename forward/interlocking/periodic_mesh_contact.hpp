#pragma once
// Contact between the mesh bodies of a periodic cell (docs/interlocking.md, "Mesh bodies in
// cells"): the IPC barrier on triangles (point-triangle and edge-edge pairs, Li et al. 2020,
// forward/contact) through the rigid maps x = T + R(w) V (forward/rigid, RigidContactTerm), over
// the cell's bodies in its order (masters first, then images; 6 DOFs each, the cell's full state
// x). Images follow their masters through the cell's Elimination (T_j = T_i + F t_ij, w_j = w_i),
// so the cell equilibrium's reduced quantities S^T dB/dx, S^T H S are those of this energy.
//
// Every pair once: images are marked fixed in the rigid system, which puts them into one contact
// group, so image-image primitive pairs are never candidates (they repeat master-image pairs of
// another cell), exactly as for the implicit tori (periodic_cell.hpp). Broad phase: sweep and
// prune over the boxes of every primitive of masters and images (forward/contact/broad_phase).
// Step bound: additive CCD on the curved rigid paths (ContactBodies::max_step), so a Newton step
// or a ramp prediction never passes through an intersection.
//
// Units: kappa is set so that one primitive pair at d_hat / 2 pushes with unit force (the
// barrier acts on squared distances, contact::stiffness_for_force), like the tori's pairs.
//
// The cell's contact functions (cell_equilibrium.hpp) hand a mesh cell's evaluations to this
// class; body pairs are reported as for tori (a, b bodies, a < b), with the body pair's distance
// the smallest over its primitive pairs.
#include <memory>
#include <vector>

#include "forward/interlocking/periodic_mesh_elements.hpp"
#include "forward/rigid/rigid_contact_term.hpp"

namespace tailor::interlocking {

class PeriodicMeshContact {
 public:
  // body_meshes: per body of the cell (masters then images) its master's mesh; the first
  // `num_masters` are free, the rest images; rest_state: the cell's x at the rest placement (6 per
  // body); in_reach: per body, whether it takes part in contact at all (images that never come
  // near a master are left out: the broad phase's sweep would compare their primitives with
  // everything along its axis). The contact works on the selected bodies' DOFs internally and
  // reads and writes the cell's full x.
  PeriodicMeshContact(const std::vector<std::shared_ptr<const ElementMesh>>& body_meshes, int num_masters,
                      const Vector& rest_state, const std::vector<bool>& in_reach, double activation_distance);

  double activation_distance() const { return term_->potential().options().activation_distance; }
  double stiffness() const { return term_->potential().options().stiffness; }
  // The IPC term over the selected bodies' DOFs (contact body c is the cell's body cell_body(c)).
  const rigid::RigidContactTerm& term() const { return *term_; }
  int cell_body(int contact_body) const { return bodies_[static_cast<std::size_t>(contact_body)]; }
  int num_contact_bodies() const { return static_cast<int>(bodies_.size()); }
  Vector contact_state(const Vector& x) const;  // the selected bodies' 6-blocks of the cell's x
  const rigid::RigidBodySystem& system() const { return *system_; }
  int num_triangles() const { return static_cast<int>(system_->surface().faces.rows()); }

  // B(x) (+infinity for an intersecting state), dB/dx (+=) and the full Hessian (both triangles;
  // projected per pair in projected mode). Null outputs are not computed.
  void evaluate(const Vector& x, double* energy, Vector* gradient, SparseMatrix* hessian, HessianMode mode) const;
  // The largest safe fraction of the step x -> x + dx (additive CCD on the rigid paths).
  double max_step(const Vector& x, const Vector& dx) const;
  // The smallest primitive distance over pairs within `range` (infinity if none; an infinite range
  // is capped at the smallest mesh radius, beyond which nothing matters to a lock-up).
  double min_distance(const Vector& x, double range) const;
  // Body pairs with a primitive pair within `range`, their distance the smallest (no derivatives;
  // the per-pair torus fields stay at their defaults).
  std::vector<tori::TorusPair> close_pairs(const Vector& x, double range) const;
  // Body pairs with active primitive pairs (within d_hat): distance and the force on b (the sum of
  // -dB/dx over b's stencil vertices) [unit pair force].
  std::vector<tori::TorusPairForce> pair_forces(const Vector& x) const;

 private:
  std::unique_ptr<rigid::RigidBodySystem> system_;
  std::unique_ptr<rigid::RigidContactTerm> term_;
  std::vector<int> bodies_;  // contact body -> cell body
  int num_cell_bodies_ = 0;
  double range_cap_ = 0.0;
};

// An intersection check of a mesh cell's state that shares no code with the contact model: every
// pair of triangles of two bodies that the contact model considers (masters with masters and
// images) is tested for intersection of the closed triangles with exact orientation predicates
// (a filtered double evaluation, decided exactly by expansion arithmetic where the filter cannot,
// Shewchuk 1997). Two triangles in general position meet iff an edge of one meets the other;
// coplanar touching pairs are counted as intersecting (conservative). Containment of a whole
// surface inside another is not detected (interlocked rings cannot reach it without crossing).
struct MeshIntersectionReport {
  long triangle_pairs = 0;  // pairs whose bounding boxes overlap (tested exactly)
  long intersecting = 0;    // pairs that meet
  long exact_fallbacks = 0; // orientation signs the filter left to the exact evaluation
  bool apart() const { return intersecting == 0; }
};
MeshIntersectionReport check_mesh_intersections(const PeriodicRigidCell& cell, const Vector& x);

// The sign (-1, 0, 1) of the orientation determinant det[b - a, c - a, d - a], exact.
int exact_orientation(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                      const Eigen::Vector3d& d, long* fallbacks = nullptr);

}  // namespace tailor::interlocking
