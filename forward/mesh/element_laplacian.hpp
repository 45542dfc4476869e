#pragma once
// The element face-adjacency graph Laplacian of a simplicial mesh (material smoothness
// regularisation, Laplacian material modes):
//   L_ee = sum_f w_ef,  L_ef = -w_ef  for elements e != f sharing a facet.
// Weights:
//   unit:                w_ef = 1.
//   facet_over_distance: w_ef = |F_ef| / |c_e - c_f| (shared facet measure over the distance of
//                        the rest centroids; the two-point flux approximation, so y^T L y
//                        approximates the integral of |grad y|^2).
#include "forward/core/types.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor {

enum class AdjacencyWeighting { unit, facet_over_distance };

// One weight per row of `pairs` (as from element_adjacency). Throws std::invalid_argument for an
// empty or non-simplicial mesh, or (facet_over_distance) a degenerate shared facet or coincident
// centroids.
Vector element_adjacency_weights(const Mesh& mesh, const Eigen::MatrixXi& pairs, AdjacencyWeighting weighting);

// L (num_elements^2, symmetric, full storage, rows summing to zero). Throws as above.
SparseMatrix element_adjacency_laplacian(const Mesh& mesh, AdjacencyWeighting weighting = AdjacencyWeighting::unit);

}  // namespace tailor
