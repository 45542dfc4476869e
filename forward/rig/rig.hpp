#pragma once
// An animation rig: linear blend skinning over a bone hierarchy plus pose-space corrections
// (docs/pose_space.md; Xu & Barbic 2016, "Pose-space subspace dynamics", section 3;
// docs/methods.md section 17):
//
//   X(p) = sum_b w_vb T_b(p) [Xbar_v; 1]  +  sum_i w_i(p) delta_i,
//
// positions in the mesh's length unit, one row per vertex, DOFs interleaved (x0, y0, z0, x1, ...).
// Bone b's transform is T_b = T_parent(b) L_b(p_b), L_b = Tr(j_b) G_1(p_1) ... G_k(p_k) Tr(-j_b)
// with j_b the bone's joint (rest position of its pivot) and G a rotation about a unit axis
// through the joint [rad] or a translation along a unit axis [length]; T_b = I at p = 0, so p = 0
// is the rest (bind) pose Xbar.
//
// Pose weights: the normalized RBF weights w_i = phi(|p - p_i|) / sum_j phi(|p - p_j|) with the
// inverse-quadratic kernel phi(d) = 1 / d^2, written without the singularity as
//   w_i = psi_i / sum_m psi_m,  psi_i = prod_{j != i} |p - p_j|^2,
// a rational function of p, smooth everywhere, with w(p_i) = e_i (the corrections and the bases
// of example pose i are reproduced exactly there).
//
// Derivatives are exact: dX/dp (3n x P) and the contraction sum_kl d2X/dp_k dp_l a_k b_l, from
// the closed-form derivatives of the elementary rotations (R' = cos K + sin K^2,
// R'' = -sin K + cos K^2 for R = I + sin K + (1 - cos) K^2) through the hierarchy.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "forward/core/types.hpp"

namespace tailor {

enum class BoneDofType { rotation, translation };

struct BoneDof {
  BoneDofType type = BoneDofType::rotation;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // unit, in rest coordinates
};

struct Bone {
  std::string name;
  int parent = -1;                             // index of an earlier bone, -1 for a root
  Eigen::Vector3d joint = Eigen::Vector3d::Zero();  // pivot at rest
  std::vector<BoneDof> dofs;                   // parameters p, in order, owned by this bone
};

struct PoseCorrection {
  Vector pose;           // p_i (size P)
  Matrix displacement;   // delta_i, n x 3 (zero allowed)
};

// Values and derivatives of the bone transforms (4 x 4 affine) at p.
struct BoneTransforms {
  std::vector<Eigen::Matrix4d> transform;                // T_b
  std::vector<std::vector<Eigen::Matrix4d>> first;       // [b][k] dT_b/dp_k
  std::vector<std::vector<Eigen::Matrix4d>> second;      // [b][k * P + l] d2T_b/dp_k dp_l (when asked)
};

// Pose weights and their derivatives: w (m), dw/dp (m x P), d2w_i/dp2 (P x P each, when asked).
struct PoseWeights {
  Vector w;
  Matrix gradient;
  std::vector<Matrix> hessian;
};

// The motion of the rig parameters at one time: p, dp/dt, d2p/dt2.
struct PoseMotion {
  Vector p, velocity, acceleration;
};

class Rig {
 public:
  // bones: parents before children; weights: n x bones, rows summing to 1 (within 1e-9), entries
  // >= 0; rest_positions: n x 3. Throws std::invalid_argument naming the bone or vertex at fault.
  Rig(std::vector<Bone> bones, Matrix rest_positions, Matrix weights, std::vector<PoseCorrection> corrections = {});

  int num_parameters() const { return num_parameters_; }
  int num_bones() const { return static_cast<int>(bones_.size()); }
  int num_vertices() const { return static_cast<int>(rest_positions_.rows()); }
  const std::vector<Bone>& bones() const { return bones_; }
  const Matrix& rest_positions() const { return rest_positions_; }
  const Matrix& weights() const { return weights_; }
  const std::vector<PoseCorrection>& corrections() const { return corrections_; }
  // First parameter index of bone b.
  int parameter_offset(int b) const { return offsets_[static_cast<std::size_t>(b)]; }

  BoneTransforms bone_transforms(const Vector& p, bool second_derivatives) const;
  PoseWeights pose_weights(const Vector& p, bool second_derivatives) const;  // over corrections()

  // X(p), 3n interleaved [length].
  Vector rest_shape(const Vector& p) const;
  // X restricted to the given vertices (3 per vertex, in that order).
  Vector rest_shape_of(const Vector& p, const std::vector<int>& vertices) const;
  // dX/dp, 3n x P.
  Matrix rest_shape_jacobian(const Vector& p) const;
  // sum_kl d2X/dp_k dp_l a_k b_l, 3n.
  Vector rest_shape_second(const Vector& p, const Vector& a, const Vector& b) const;
  // d2X/dt2 along a motion: J(p) pddot + sum_kl d2X/dp_k dp_l pdot_k pdot_l [length / time^2].
  Vector rest_shape_acceleration(const PoseMotion& motion) const;

  // The linear map of skinning: X = sum_b B_b vec12(T_b) + sum_i w_i delta_i, with vec12 the
  // column-major top 3 x 4 block of T_b; B_b is 3n x 12 (column r + 3 c of T_b entry (r, c)).
  Matrix skinning_basis(int b) const;
  // d2T_b/dt2 (top 3 x 4, vec12) along a motion, per bone: 12 x bones.
  Matrix bone_accelerations(const PoseMotion& motion) const;
  // d2w/dt2 along a motion, per correction.
  Vector weight_accelerations(const PoseMotion& motion) const;

 private:
  std::vector<Bone> bones_;
  Matrix rest_positions_, weights_;
  std::vector<PoseCorrection> corrections_;
  std::vector<int> offsets_;
  int num_parameters_ = 0;
};

Eigen::Matrix<double, 12, 1> vec12(const Eigen::Matrix4d& transform);

// The normalized inverse-quadratic RBF weights above over any example poses (size m >= 1; one
// pose: w = 1), with dw/dp and, when asked, the Hessians. Poses must be distinct.
PoseWeights normalized_pose_weights(const std::vector<Vector>& poses, const Vector& p, bool second_derivatives);

}  // namespace tailor
