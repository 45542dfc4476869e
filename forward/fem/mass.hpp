#pragma once
// Mass matrices of linear simplicial elements, size (dim * num_vertices)^2, interleaved DOFs.
#include "forward/core/types.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor {

enum class MassLumping { consistent, lumped };

// density: per element [mass / volume] (per unit thickness in 2D).
// consistent: M_ab = rho V (1 + delta_ab) / ((d + 1)(d + 2)) per component;
// lumped: row sums of the consistent matrix on the diagonal, rho V / (d + 1) per vertex.
SparseMatrix mass_matrix(const Mesh& mesh, const Eigen::VectorXd& density, MassLumping lumping);

}  // namespace tailor
