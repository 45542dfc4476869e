#pragma once
// Per-pose reduced bases and their blending in pose space (Xu & Barbic 2016, section 5;
// docs/methods.md section 17).
//  - At each example pose p_i the body's rest shape is X(p_i); its basis U_i holds first the
//    static responses to the rig's own motion loads K^-1 M dX/dp_k, K^-1 M d2X/dp_k dp_l (and
//    gravity's K^-1 M g), then the lowest
//    vibration modes of the fixed-region-constrained mesh (with the pose's contacts as bilateral
//    constraints C phi = 0, constrained_modes.hpp), the static responses to the rig's
//    inertial loads (K^-1 M B_b per bone, the shapes a bone's acceleration pushes the body into
//    quasi-statically) and the modal derivatives of the lowest modes, mass-orthonormalized in that order and truncated to r columns.
//  - Orthogonal Procrustes aligns every U_i to U_0: R_i = V W^T with U_i^T M U_0 = V S W^T
//    minimizes |U_i R - U_0|_M over orthogonal R, so that blending combines like with like.
//  - At run time U(p) = (sum_i w_i(p) U_i R_i) L^-T with L L^T = sum_ij w_i w_j (U_i R_i)^T M (U_j R_j),
//    i.e. the blend re-orthonormalized in the mass inner product, O(m^2 r^3) with the Gram blocks
//    precomputed (nothing proportional to the mesh). At p_i, w = e_i and U(p_i) = U_i R_i.
#include <vector>

#include "forward/rig/rigged_body.hpp"

namespace tailor {

// R (r x r orthogonal) minimizing |basis R - reference|_M (both n x r).
Matrix procrustes_rotation(const Matrix& basis, const Matrix& reference, const SparseMatrix& mass);

struct ExamplePoseBasisOptions {
  int linear_modes = 10;      // lowest constrained vibration modes
  int derivative_modes = 4;   // modes whose pairwise modal derivatives are added
  // Static responses to the rig's own motion loads at the pose, K^-1 M dX/dp_k,
  // K^-1 M d2X/dp_k dp_l and K^-1 M g, placed first (before the modes).
  bool motion_responses = true;
  bool inertial_responses = true;  // static responses to the rig's inertial loads K^-1 M B_b
  int size = 20;              // r: columns kept (motion responses, modes, bone responses, derivatives)
};

// The basis U_i (3n x r, zero on fixed vertices, U^T M U = I) at rest shape X(pose).
// contact_constraints: m x 3n rows of bilateral constraints C u = 0 (empty: none).
// Throws std::invalid_argument when the body has no fixed vertex (K would be singular) or r is
// larger than the candidates; std::runtime_error when a solve fails.
Matrix example_pose_basis(const Rig& rig, const RiggedBody& body, const Vector& pose, const SparseMatrix& mass,
                          const Matrix& contact_constraints, const ExamplePoseBasisOptions& options);

// Rows of normal-contact constraints n . (u_a - u_b) = 0 between vertex pairs of the rig shape
// X(pose) closer than `distance` that belong to different bones (largest skinning weight) and
// were more than 2 distance apart in the bind pose (neighbours there are not contacts),
// n = (x_a - x_b) / |x_a - x_b|; each vertex paired with its nearest such vertex, each pair once. m x 3n.
Matrix contact_constraints_at(const Rig& rig, const Vector& pose, const std::vector<int>& surface_vertices,
                              double distance);

class PoseSpaceBasis {
 public:
  // bases: U_i at the example poses (all n x r, M-orthonormal); aligned to bases[0].
  PoseSpaceBasis(std::vector<Matrix> bases, const SparseMatrix& mass);

  int size() const { return static_cast<int>(aligned_.front().cols()); }
  int poses() const { return static_cast<int>(aligned_.size()); }
  const Matrix& aligned(int i) const { return aligned_[static_cast<std::size_t>(i)]; }
  const Matrix& rotation(int i) const { return rotations_[static_cast<std::size_t>(i)]; }
  // (U_i R_i)^T M (U_j R_j).
  const Matrix& gram(int i, int j) const { return gram_[static_cast<std::size_t>(i * poses() + j)]; }

  // L^-T for the weights w: U(p) = (sum_i w_i aligned(i)) * orthonormalizer(w).
  Matrix orthonormalizer(const Vector& w) const;
  // U(p) in full (n x r), for output and comparisons.
  Matrix blend(const Vector& w) const;

 private:
  std::vector<Matrix> aligned_, rotations_, gram_;
};

}  // namespace tailor
