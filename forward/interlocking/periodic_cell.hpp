#pragma once
// A periodic cell of rigid interlocking tori (docs/interlocking.md).
//
// The cell holds N master elements (implicit tori with rigid DOFs (T_i, w_i), forward/rigid) and
// the lattice vectors t1, t2 (columns of `lattice`, in the xy plane). Under a macro deformation
// gradient F (2 x 2, acting on x and y; z is not deformed) the image of master i shifted by
// the lattice combination k = (a, b) sits at
//   T_(i,k) = T_i + F (a t1 + b t2),   w_(i,k) = w_i,
// so the images' DOFs follow their masters: x = x0(F) + S y is an Elimination on the rigid DOFs
// of masters and images (x: 6 per body, masters first), y the free master DOFs. The anchor
// master's translation is held in x0 (it removes the cell's rigid translations); its rotation
// stays free.
//
// Images are kept for the shifts of half the lattice, k = (a, b) with 0 < a <= K or (a = 0,
// 0 < b <= K), |a|, |b| <= K = image_rings. Then every periodic pair class {(i, j + k),
// (j, i - k)} appears exactly once as a master-image pair, and master-master pairs once: the
// contact energy is the energy of one cell, with no pair counted twice. Images are marked fixed
// in the rigid system so that the contact term skips image-image pairs (they repeat master-image
// pairs of another cell); their poses are read from x like any body's. Shifts beyond K must never
// come within reach; PeriodicRigidCell checks this at F = I with a margin (`reach_margin`).
//
// Contact is the implicit torus barrier of forward/tori (TorusContactTerm) with the radii read
// from p: p = (R, r) per body, each image carrying its master's radii (radii_map()).
// Energy units: kappa is set so that one pair at distance d_hat / 2 pushes with unit force.
#include <Eigen/Core>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "forward/core/elimination.hpp"
#include "forward/rigid/rigid_body_system.hpp"
#include "forward/tori/torus_contact_term.hpp"

namespace tailor::interlocking {

struct ElementMesh;          // periodic_mesh_elements.hpp
class PeriodicMeshContact;   // periodic_mesh_contact.hpp

struct CellElement {
  tori::TorusShape shape;                              // circular or elliptic tube
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // rest T [length]
  Eigen::Vector3d rotation = Eigen::Vector3d::Zero();  // rest w [rad]
  bool rim = false;  // bending patches: the element is prescribed on the surface (see below)
  // Bending patches cut from a tiling (disc_patch): the tiling's element this one copies, so that a
  // design can tie every copy's radii; -1: none (the element is itself).
  int origin = -1;
  // A triangle-mesh body instead of the implicit torus (periodic_mesh_elements.hpp): contact is
  // then the IPC barrier on the meshes (periodic_mesh_contact.hpp); `shape` is not used by the
  // contact. A cell's elements are all meshes or all tori.
  std::shared_ptr<const ElementMesh> mesh = nullptr;
};

struct RigidCellSpec {
  std::vector<CellElement> elements;
  Eigen::Matrix2d lattice = Eigen::Matrix2d::Identity();  // columns t1, t2 [length]
  int image_rings = 1;                                    // K above
  double activation_distance = 0.0;                       // d_hat [length]; 0: 1e-3 min R
  int anchor = 0;                                         // master whose translation is held
  // Shifts beyond K are refused if two bounding spheres come within this fraction of the cell's
  // smallest lattice vector length at F = I (room for the strains the sweeps apply).
  double reach_margin = 0.2;
  // Which pairs the cell's own contact evaluations (cell_equilibrium.hpp) look at: false, every
  // master-master and master-image pair through the contact term (the reference); true, the
  // grid broad phase's candidates (candidate_pairs below), with identical results.
  bool broad_phase = true;
  // A finite bending patch instead of a periodic cell (docs/interlocking.md, "Bending"): no
  // images (lattice, image_rings and anchor unused); the macro argument F stands for the
  // curvature tensor K = sym(F) - I of the paraboloid z = 1/2 p^T K p (p = (x, y)), i.e.
  // z = A x^2 + B y^2 + C x y with A = K_xx / 2, B = K_yy / 2, C = K_xy. Rim elements are
  // prescribed on it: rest position (x, y, z) goes to (x, y, f(x, y)) + z n(x, y) and rest rotation
  // R to Q R, Q the smallest rotation taking e_z to the normal n. The others are free (6 DOFs
  // each). Rim-rim pairs are contact pairs too (a collision of prescribed elements also locks).
  // Needs broad_phase. x0(F) is nonlinear in K; its first derivative along a curvature path
  // (offset_derivative) is what the augmented Newton and the limit derivatives need.
  bool bending_patch = false;
};

// Throws std::invalid_argument naming the problem (no elements, singular lattice, bad shape,
// anchor out of range, overlapping elements at rest, images beyond K within reach).
void validate_cell(const RigidCellSpec& spec);

class PeriodicRigidCell {
 public:
  explicit PeriodicRigidCell(RigidCellSpec spec);

  const RigidCellSpec& spec() const { return spec_; }
  int num_elements() const { return static_cast<int>(spec_.elements.size()); }
  int num_bodies() const { return static_cast<int>(master_.size()); }  // masters and images
  int num_free() const { return static_cast<int>(basis_.cols()); }    // 6 N - 3
  int master(int body) const { return master_[static_cast<std::size_t>(body)]; }
  const Eigen::Vector2i& shift(int body) const { return shift_[static_cast<std::size_t>(body)]; }
  double activation_distance() const { return d_hat_; }
  const tori::TorusContactTerm& contact() const { return *contact_; }
  // Mesh cells (CellElement::mesh): their contact (contact() is not built for them); null for a
  // cell of implicit tori.
  const PeriodicMeshContact* mesh_contact() const { return mesh_contact_.get(); }

  // The Elimination x = x0(F) + S y at macro F; S is the same for every F.
  Elimination elimination(const Eigen::Matrix2d& F) const;
  const SparseMatrix& basis() const { return basis_; }
  Vector offset(const Eigen::Matrix2d& F) const;                // x0(F)
  // Bending patches: the curvature tensor K = sym(F) - I of a macro argument F, and the pose on
  // the paraboloid z = 1/2 p^T K p of an element at rest pose (position, rotation) (see spec).
  static Eigen::Matrix2d curvature(const Eigen::Matrix2d& F);
  static void surface_pose(const Eigen::Matrix2d& K, const Eigen::Vector3d& position, const Eigen::Vector3d& rotation,
                           Eigen::Vector3d& T, Eigen::Vector3d& w);
  // The derivative (dT, dw) of surface_pose along a curvature direction dK (symmetric), exact:
  // n = m / |m|, m = (-K p, 1); Q = I + [v] + [v]^2 / (1 + n_z), v = e_z x n (the smallest
  // rotation, the same as surface_pose's axis-angle form); dw from the angular velocity
  // vee(dR R^T) of R = Q R0 by the inverse of the rotation vector's Jacobian (rigid/rotation.hpp).
  static void surface_pose_derivative(const Eigen::Matrix2d& K, const Eigen::Matrix2d& dK,
                                      const Eigen::Vector3d& position, const Eigen::Vector3d& rotation,
                                      Eigen::Vector3d& dT, Eigen::Vector3d& dw);
  // dx0/ds along F(s) with dF/ds = dF at F: periodic cells, the image translations' rows
  // (F L k)' = dF L k (independent of F); bending patches, the rim poses' derivative along
  // dK = sym(dF) at K = curvature(F) (nonlinear in K).
  Vector offset_derivative(const Eigen::Matrix2d& F, const Eigen::Matrix2d& dF) const;
  Vector full_state(const Vector& y, const Eigen::Matrix2d& F) const;  // x0(F) + S y
  // y of the rest placement (the anchor's translation is in x0, not in y).
  Vector rest_free_state() const;
  // The master rigid DOFs (6 N) from y (the anchor's translation filled in).
  Vector master_state(const Vector& y) const;

  // dx/dF_kl (k, l in {0, 1}): the image translations' rows, e_k (L shift)_l; independent of F.
  Vector state_derivative_macro(int k, int l) const;
  // dx/dL_kl at F: the image translations' rows, F e_k shift_l (L the lattice matrix).
  Vector state_derivative_lattice(const Eigen::Matrix2d& F, int k, int l) const;
  // p for the contact term: (R, r) of every body (images: their master's).
  Vector radii_parameters() const;
  // P (2 bodies x 2 N): body radii = P master radii.
  SparseMatrix radii_map() const;

  // The master element and shift of each image within the same pair ordering as the contact
  // term's pairs: a pair of bodies (a, b) is the periodic pair (master(a), master(b) + shift(b)
  // - shift(a)).
  std::string pair_label(int a, int b) const;

  // Broad phase (docs/interlocking.md, "Broad phase"): the body pairs (a < b, not two images)
  // whose bounding spheres about T at x, each grown by the length of its translation along dx
  // when dx is given, come within `range` (finite) of each other, in (a, b) order. Found through a
  // uniform grid of spacing (largest grown diameter + range) over the centres, so only bodies in
  // neighbouring grid cells are compared. A superset of the pairs that the contact term's
  // all-pairs sphere tests keep (close_pairs: |T_a - T_b| < reach + range; max_step: |T_a - T_b|
  // - |dT_a - dT_b| <= reach), which are applied to the candidates unchanged.
  std::vector<std::pair<int, int>> candidate_pairs(const Vector& x, double range, const Vector* dx = nullptr) const;

 private:
  RigidCellSpec spec_;
  double d_hat_ = 0.0;
  std::vector<int> master_;
  std::vector<Eigen::Vector2i> shift_;
  std::vector<double> bounding_;  // per body: R + max(r, r1) of its master [length]
  SparseMatrix basis_;
  std::unique_ptr<rigid::RigidBodySystem> system_;
  std::unique_ptr<tori::TorusContactTerm> contact_;
  std::shared_ptr<const PeriodicMeshContact> mesh_contact_;
  void build_mesh_contact();
};

}  // namespace tailor::interlocking
