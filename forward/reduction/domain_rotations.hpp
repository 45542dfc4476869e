#pragma once
// Per-domain rotations of a local reduced basis (docs/reduction.md, "Per-domain rotations").
//
// A linear basis (modes, modal derivatives, local columns) represents a rotation of a region
// only to the order of its Krylov blocks: a twisted or curled bar turns its sections through
// angles a fixed basis cannot follow. Here each domain d carries its own rotation R_d, fitted to
// the current displacement: the mass- and weight-weighted least-squares deformation gradient of
// the domain's vertices (the affine fit of shape matching, Mueller et al. 2005, eq. 7),
//   F_d = A_pq A_qq^{-1},  A_pq = sum_v mu_v (x_v - xbar)(X_v - Xbar)^T,
//                          A_qq = sum_v mu_v (X_v - Xbar)(X_v - Xbar)^T,   mu_v = m_v w_d(v),
// and its rotation R_d = polar(F_d) = F_d (F_d^T F_d)^{-1/2} (modal warping / rotation-strain
// coordinates rotate local modes the same way). A vertex's columns are carried by the blend of
// its domains' rotations with the domain weights, sum_d w_d(v) R_d (linear blend skinning of the
// rotated domain frames): the rotated basis is B(u) = Rbar(u) Phi, row block v = Rbar_v Phi_v.
// Linear blending of rotations that differ by more than a fraction of a radian is no rotation: it
// shrinks the blended columns (the candy-wrapper artefact of linear blend skinning). Two blends
// avoid it: the normalized blend of the domains' unit quaternions (sign-aligned; the rotation part
// of dual-quaternion skinning, Kavan et al. 2008), and rigid frames on a partition (each vertex
// takes the rotation of its heaviest domain).
// Positions and displacements are vertex-interleaved (x, y, z); 3D only.
#include <vector>

#include <Eigen/Core>

#include "forward/core/types.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor {

// Weights of the domains of a partition at the vertices: the fraction of the volume of a vertex's
// elements that lies in domain d (num_vertices x domains; rows sum to 1; a vertex interior to
// domain d has w_d = 1). For overlapping domains use OverlappingDomains::weights instead.
Matrix domain_vertex_weights(const Mesh& mesh, const Eigen::VectorXi& element_domain);

// R_d for every domain (columns of `weights`) at the displacement u (num_vertices * 3, from the
// rest positions); vertex_mass: num_vertices, > 0 where the fit should look (e.g. lumped masses).
// A domain whose fit is singular (fewer than 4 non-coplanar weighted vertices) or inverted
// (det F_d <= 0) gets the identity. Throws std::invalid_argument on bad sizes or a 2D mesh.
std::vector<Eigen::Matrix3d> fit_domain_rotations(const Mesh& mesh, const Vector& displacement,
                                                  const Vector& vertex_mass, const Matrix& weights);

// The closest rotation to F (polar decomposition, F = R S with S symmetric positive definite);
// requires det F > 0.
Eigen::Matrix3d polar_rotation(const Eigen::Matrix3d& F);

// How a vertex's rotation is formed from its domains' rotations R_d and weights w_d(v).
enum class RotationBlend {
  linear,      // sum_d w_d R_d (linear blend skinning; not a rotation where the R_d differ)
  quaternion,  // the rotation of the unit quaternion sum_d w_d s_d q_d / |.|, s_d = sign(q_d . q_heaviest)
  nearest,     // R_d of the domain with the largest w_d(v) (rigid frames on a partition)
};

// The blended rotation (or, for linear, blended matrix) of one vertex from its row of weights.
Eigen::Matrix3d blend_rotations(const Eigen::Ref<const Eigen::RowVectorXd>& weights,
                                const std::vector<Eigen::Matrix3d>& rotations, RotationBlend blend);

// B = Rbar Phi: row block v of `basis` (num_vertices * 3 x r) times the blend of the rotations
// with weights(v, :).
Matrix rotate_basis(const Matrix& basis, const Matrix& weights, const std::vector<Eigen::Matrix3d>& rotations,
                    RotationBlend blend = RotationBlend::linear);

// Per-vertex masses of a mass matrix: the row sums of a vertex's x rows (= rho V / 4 summed over
// its tets for the consistent and the lumped tet mass).
Vector vertex_masses(const SparseMatrix& mass);

}  // namespace tailor
