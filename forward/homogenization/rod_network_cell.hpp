#pragma once
// Periodic cells of rod networks (docs/homogenization.md, "Rod-network cells"): discrete elastic
// rods (forward/rods: stretching, bending, twisting) between the joints of a planar lattice,
// homogenized to the effective in-plane (membrane) stiffness by the macro-strain loads of the
// FEM cells (linear_homogenization.hpp).
//
// Geometry: the cell is the parallelogram of the lattice vectors a_1, a_2 (columns of A, in the
// xy-plane, z = 0). Joints sit in the cell; a bar runs from joint `from` to the image of joint
// `to` in the cell shifted by A s (s integer), and is one open DiscreteRod of `edges_per_bar`
// straight edges. Periodicity, as for the FEM cells, is an Elimination x = x0 + S y on the
// positions:
//   x_v = (I + H) X_v + w_{joint(v)}     (a bar's end vertices, X_v = X_joint + A s),
//   x_v = (I + H) X_v + w_v              (interior vertices), w_anchor = 0 (joint 0),
// so an image vertex sits at x_joint + (I + H) A s: the macro strain drives the image offsets.
// Joints: every bar end at a joint (master or image) is a member of that joint's
// RodRigidJointTerm, whose three rotation DOFs are shared by the joint and all its images
// (omega_image = omega_master), so the frames are periodic; twist angles are per edge and each
// edge exists once in the cell, so they need no images.
// Units: lengths [length], moduli [pressure]; the membrane stiffness C (Voigt (11, 22, 12),
// engineering shear) is force per length: the energy per unit cell area is 1/2 eps^T C eps,
// and C / depth is the modulus of a sheet of that depth.
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "forward/core/model.hpp"
#include "forward/homogenization/rod_network.hpp"

namespace tailor {

// Declared only: includers (tests, scenes, bench) need not parse the rods' and CHOLMOD's headers.
class DiscreteRod;
class ReducedAssembler;
class SparseCholesky;
struct RodParameterBlocks;

struct RodNetworkHomogenization {
  Matrix stiffness;             // C (3 x 3, Voigt (11, 22, 12)) [force / length]
  std::vector<Vector> states;   // per load case: x = rest + u_I (all DOFs)
  double symmetry_error = 0.0;  // max |C - C^T| / max |C|
  double assembly_seconds = 0.0;
  double factorization_seconds = 0.0;
  double solve_seconds = 0.0;
};

class RodNetworkCell {
 public:
  // Builds the rods, their energies, the joints and the periodic elimination at H = 0. Throws
  // std::invalid_argument from RodNetwork::validate().
  explicit RodNetworkCell(RodNetwork network);
  ~RodNetworkCell();
  RodNetworkCell(const RodNetworkCell&) = delete;
  RodNetworkCell& operator=(const RodNetworkCell&) = delete;

  const RodNetwork& network() const { return network_; }
  Model& model() { return *model_; }
  const Model& model() const { return *model_; }
  const Vector& parameters() const { return parameters_; }
  const Vector& rest_state() const { return rest_; }
  // One rod per bar, and its parameter blocks (prefix "bar<b>").
  const std::vector<std::shared_ptr<DiscreteRod>>& rods() const { return rods_; }
  const std::vector<RodParameterBlocks>& rod_blocks() const { return blocks_; }
  int num_free() const;

  // x0 of the elimination for an in-plane macro displacement gradient H (2 x 2): positions
  // (I + H) X, twists and joint rotations zero.
  Vector macro_offset(const Matrix& macro_gradient) const;

  // The 3 unit macro strains (unit_macro_strain(2, I)) as linear cell problems about the
  // stress-free rest state: S^T K S y_I = -S^T K u0_I with K the exact Hessian of the rod
  // energies at rest, u_I = u0_I + S y_I, C_IJ = u_I^T K u_J / |Y| (the energy form, as for the
  // FEM cells). One CHOLMOD factorization for the three; K u by one assembled K (solve_seconds
  // includes its assembly). Throws std::runtime_error when the
  // periodic stiffness is not positive definite (a mechanism).
  RodNetworkHomogenization solve();

 private:
  RodNetwork network_;
  std::unique_ptr<Model> model_;
  std::unique_ptr<ReducedAssembler> assembler_;
  std::vector<std::shared_ptr<DiscreteRod>> rods_;
  std::vector<RodParameterBlocks> blocks_;
  std::vector<Eigen::Vector3d> rest_positions_;  // per position DOF triple, in DOF order
  std::vector<int> position_dofs_;               // first DOF of each vertex
  SparseMatrix hessian_;
  std::unique_ptr<SparseCholesky> factor_;
  Vector parameters_;
  Vector rest_;
};

}  // namespace tailor
