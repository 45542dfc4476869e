#pragma once
// Nodes and background quadrature of an analytic solid (docs/meshless.md, "Nodes and quadrature").
//
// Octree: the bounding box is covered by cubic cells of edge h (the roots of a forest of
// octrees, one per cell; the grid starts at the box's lower corner and has ceil(extent / h)
// cells per axis). Node levels: a cell of edge e = h 2^-l (level l < max_level) that is not
// wholly outside is split into 8 octants where
//   - a refinement box of a level above l meets it, or
//   - refine_thin is set and the solid is thin there: the largest depth -d over the 7^3 probes
//     spaced e / 2 over the cell enlarged by e on every side is below e (the solid is thinner
//     than about 2 e near the cell: fewer than 3 node layers would cross it).
// The leaves are the node cells. Nodes are placed per octant at the leaves' corners that lie in
// the closed solid (d <= 1e-9 e), each with the spacing of the finest leaf it is a corner of; a
// leaf's corners on a finer neighbour's face are shared (no 2:1 balance is enforced: the MLS
// supports need none, covering_patches.hpp sizes them per point).
//
// Quadrature: every leaf is classified by the signed distance at its centre c and its
// half-diagonal r = sqrt(3) e / 2 (valid for the 1-Lipschitz distances of analytic_shape.hpp):
//   d(c) <= -r  wholly inside: the tensor Gauss-Legendre rule of `quadrature_order` points per
//               axis, kept whole;
//   d(c) >=  r  wholly outside: dropped;
//   otherwise   cut by the boundary: split into 8 octants, recursively, down to
//               `boundary_depth` levels below the leaf; a cut cell at that depth keeps the Gauss
//               points of its rule that are inside (d <= 0) with their full weights and drops
//               the others.
// The volume error is that of the dropped and kept parts of the cut leaves: at most about the
// cut leaves' volume, O(h 2^-depth); their errors have both signs and partly cancel, and the
// sphere's measured error falls faster (tests/forward/meshless/sampling_test.cpp, docs/meshless.md).
#include <Eigen/Core>
#include <vector>

#include "forward/meshless/analytic_shape.hpp"

namespace tailor {

// Cells meeting the box [lo, hi] get nodes at least `level` octree levels below the root.
struct OctreeRefinementBox {
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
  int level = 1;
};

struct OctreeSamplingOptions {
  double spacing = 0.0;       // h, the coarsest node spacing and root cell edge (> 0)
  int quadrature_order = 3;   // Gauss points per axis per leaf cell (1 to 8)
  int boundary_depth = 2;     // octree levels below a node cell for cells cut by the boundary (0 to 8)
  int max_level = 0;          // node levels below the root cells (0: uniform spacing h; at most 6)
  bool refine_thin = true;    // with max_level > 0: split where the solid is thin (see above)
  std::vector<OctreeRefinementBox> refine_boxes{};  // levels above max_level are refused
};

struct OctreeSampling {
  Eigen::MatrixXd nodes;       // n x 3 rest positions
  Eigen::VectorXd spacing;     // per node: the node spacing around it (the finest leaf's edge)
  Eigen::VectorXi level;       // per node: its octree level (spacing = h 2^-level)
  Eigen::MatrixXd points;      // quadrature points, q x 3
  Eigen::VectorXd weights;     // their weights (volume)
  int cells_inside = 0;        // node cells (leaves) wholly inside
  int cells_cut = 0;           // node cells cut by the boundary
  int cells_refined = 0;       // cells split for node levels
  int leaves_cut = 0;          // cut cells at the deepest level (where points were dropped)
  double volume() const { return weights.sum(); }
};

// Gauss-Legendre points and weights on [-1, 1] (order 1 to 8).
void gauss_legendre(int order, std::vector<double>& points, std::vector<double>& weights);

// std::invalid_argument on a bad option or when no node lies inside the solid.
OctreeSampling sample_shape(const AnalyticShape& shape, const OctreeSamplingOptions& options);

}  // namespace tailor
