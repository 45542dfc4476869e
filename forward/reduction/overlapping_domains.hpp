#pragma once
// Overlapping domains blended like skinning, with principal-direction weights (Yang et al.
// 2015; docs/reduction.md, "Overlapping domains").
//
// Domain d's region R_d: the vertices of its elements, grown by `overlap_layers` rings of
// elements. Its core s: the free DOFs of the vertices of its own elements; n: the other free DOFs
// of R_d; everything outside R_d is held (C u = 0). The principal direction is the force p on
// the core, |p| = 1, whose constrained equilibrium
//   [K_ss K_sn 0; K_ns K_nn C^T; 0 C 0] [u_s; u_n; lambda] = [p; 0; 0]
// moves the body most, max |u|_M. Eliminating the held DOFs, u = S p with S = K_RR^{-1} E_s
// (E_s: the core columns of the identity), so p is the top eigenvector of the symmetric
// eigenproblem S^T M S p = mu p (equivalently the generalized eigenproblem
// M u = mu K_RR E_s E_s^T K_RR u on span(S)); it is found by subspace iteration with
// Rayleigh-Ritz on products with K_RR^{-1} (one factorization per domain).
//
// Weights: the vertex displacement magnitudes |u_d(v)| scaled to a maximum of 1, then divided
// by their sum over domains, so sum_d w_d(v) = 1 at every vertex (a vertex no principal
// displacement reaches, e.g. a clamped one, goes to the domains whose elements it touches, in
// equal parts). The blended basis has a column w_d * b per domain d and local column b:
//   u(v) = sum_d w_d(v) (B q_d)(v),
// continuous, without interface constraints or duplicated DOFs, and containing span(B) itself
// (equal coefficients in every domain add up to B q).
#include <vector>

#include "forward/core/model.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor {

struct OverlappingDomainOptions {
  int overlap_layers = 2;     // element rings added around each domain
  double tolerance = 1e-12;   // relative change of the top Ritz value that ends the iteration
  int max_iterations = 300;   // subspace iterations per domain
  int block_size = 4;         // subspace iteration block (>= 1)
};

struct OverlappingDomains {
  Matrix weights;                             // num_vertices x domains, rows sum to 1
  std::vector<Vector> principal_forces;       // per domain: p in full DOF space, |p| = 1, 0 off the core
  std::vector<Vector> principal_displacements;  // per domain: u = S p in full DOF space
  Vector principal_values;                    // per domain: mu = |u|_M^2
  std::vector<std::vector<int>> region_vertices;  // per domain, sorted
  std::vector<int> iterations;                // subspace iterations per domain
  double seconds = 0.0;
};

// Needs Dirichlet constraints (a selection elimination). Throws std::invalid_argument on bad
// sizes/options, std::runtime_error when K_RR is not positive definite (a region neither held nor
// clamped) or the iteration does not converge.
OverlappingDomains overlapping_domains(const Model& model, const Mesh& mesh, const Vector& x, const Vector& p,
                                       const SparseMatrix& mass, const Eigen::VectorXi& element_domain,
                                       const OverlappingDomainOptions& options = {});

// The blended basis: column d * c + j is weights(:, d) * local(:, j) vertex by vertex (DOFs
// interleaved in dimension dim); num_dofs x (domains * c), not orthonormalized.
Matrix blended_basis(const Matrix& weights, const Matrix& local, int dim);

// Vertices of the elements of domain d grown by `layers` rings of elements (sharing a vertex).
std::vector<int> grown_region(const Mesh& mesh, const Eigen::VectorXi& element_domain, int domain, int layers);

}  // namespace tailor
