#pragma once
// The consistent mass matrix of quadratic meshes (forward/mesh/quadratic_mesh.hpp), size
// (dim * num_nodes)^2 with interleaved DOFs:  M_(a i)(b j) = delta_ij int rho N_a N_b dV,
// integrated with the degree-4 rules (forward/fem/simplex_quadrature.hpp: 6 points per triangle,
// 11 per tet), exact on straight-sided elements. On those the element matrix is the classical one
// (Zienkiewicz & Taylor, Vol. 1, Appendix; e.g. a 6-node triangle of area A: rho A / 30 on a corner's
// diagonal, -rho A / 180 between corners, 8 rho A / 45 on an edge node's diagonal). No lumped
// variant: row sums of the P2 consistent mass are zero or negative at the corners of a tet, so
// row-sum lumping would give non-positive masses.
#include "forward/core/types.hpp"
#include "forward/mesh/quadratic_mesh.hpp"

namespace tailor {

// density: per element [mass / volume] (per unit thickness in 2D).
SparseMatrix quadratic_mass_matrix(const QuadraticMesh& mesh, const Eigen::VectorXd& density);

}  // namespace tailor
