#pragma once
// Laplacian material modes (Xu, Li, Chen, Barbic 2015): the lowest eigenpairs of
//
//   L y = lambda V y,
//
// with L the graph Laplacian of the element face-adjacency graph of a simplicial mesh
// (L_ee = sum_f w_ef, L_ef = -w_ef for elements e != f sharing a facet) and V = diag(element
// volumes). A per-element material field restricted to E = Phi z, Phi = [y_1 ... y_r], varies
// smoothly over the mesh; the first mode is the constant 1 / sqrt(total volume) (lambda = 0)
// on a connected mesh. Phi is V-orthonormal: Phi^T V Phi = I. This is the basis that
// linear_basis_map(Phi, p0) takes.
//
// Weights: see element_laplacian.hpp (with facet_over_distance the eigenvalues approximate
// those of the Neumann Laplacian of the body).
#include <string>

#include "forward/core/types.hpp"
#include "forward/mesh/element_laplacian.hpp"
#include "forward/mesh/mesh.hpp"
#include "forward/reduction/generalized_eigen.hpp"

namespace tailor {

struct MaterialModeOptions {
  AdjacencyWeighting weighting = AdjacencyWeighting::unit;
  GeneralizedEigenOptions eigen;  // passed to generalized_eigenpairs
};

struct MaterialModes {
  Matrix modes;                  // num_elements x r, V-orthonormal columns (Phi)
  Vector eigenvalues;            // r, ascending, >= 0 up to round-off
  GeneralizedEigenResult solve;  // diagnostics of the eigen solve (its eigenvectors moved out)
};

// The `count` lowest material modes. Throws std::invalid_argument for a bad mesh (as above,
// or a non-positive element volume) or count not in [1, num_elements - 1]; throws
// std::runtime_error when the eigen solve fails (its message included).
MaterialModes material_modes(const Mesh& mesh, int count, const MaterialModeOptions& options = {});

}  // namespace tailor
