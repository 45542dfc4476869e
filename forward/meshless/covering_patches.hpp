#pragma once
// MLS patches (support radii) sized per node so that every quadrature point meets the covering
// condition (docs/meshless.md, "Patches"): at least m nodes with a non-zero weight (m the basis
// size) and a moment matrix whose condition number is at most `target_condition`.
//
// Starting from R_a = support_factor * spacing_a, every point is evaluated; at a point X that
// fails, the k nearest nodes get R_a = max(R_a, |X - X_a| / reach) (their weight at X is then
// at least W(reach)), k = m + 4 on the first pass and m more on each later one. Passes repeat
// until no point fails (a pass after the first re-checks only the points that failed: a larger
// support adds a positive semi-definite term to the moment matrices it reaches, and the
// quadrature build checks every point again against max_condition); a point that still fails after `max_passes` (more than m + 4 max_passes
// nearest nodes would be needed, e.g. nodes that are all coplanar) is reported by a
// MeshlessPointError naming it. Enlarging a support only adds nodes to the points it reaches.
#include <Eigen/Core>

#include "forward/meshless/mls_shape_functions.hpp"

namespace tailor {

struct CoveringOptions {
  double target_condition = 1e4;  // of the scaled moment matrix (mls_shape_functions.hpp)
  double reach = 0.75;             // |X - X_a| / R_a of an enlarged support at the failing point
  int max_passes = 6;
};

struct CoveringReport {
  int points = 0;             // quadrature points checked
  int points_repaired = 0;    // points that failed on some pass
  int nodes_enlarged = 0;     // nodes whose support grew
  double largest_growth = 1.0;  // largest R_a over its initial value
  int passes = 0;             // evaluation passes (1: nothing to repair)
};

// Per-node spacings from each node's own neighbourhood: s_a = the distance from node a to its
// k-th nearest other node (nodes n x 3, 1 <= k < n). Handed to MlsShapeFunctions, the patches
// are R_a = support_factor * s_a: on a lattice of spacing h with k = 6 an interior node gets h
// (its six face neighbours) and a node on a face, edge or corner sqrt(2) h (it has only 5, 4
// or 3 neighbours at h), so the support is smallest in the interior and larger where the
// boundary leaves fewer nodes around a point; scattered or graded nodes get patches that follow
// their local density. cover_points then grows them only where a point still fails.
// std::invalid_argument on bad k. A uniform bucket grid finds the neighbours: O(n k) for evenly
// spread nodes.
Eigen::VectorXd neighbour_spacing(const Eigen::MatrixXd& nodes, int k);

// The per-node spacings s_a to hand to MlsShapeFunctions (R_a = support_factor * s_a) so that
// every row of `points` (q x 3) is covered; nodes n x 3, spacing per node (the initial s_a).
// MeshlessPointError for a point that cannot be covered (see above).
Eigen::VectorXd cover_points(const Eigen::MatrixXd& nodes, const Eigen::VectorXd& spacing, const Eigen::MatrixXd& points,
                             const MlsOptions& mls, const CoveringOptions& options = {},
                             CoveringReport* report = nullptr);

}  // namespace tailor
