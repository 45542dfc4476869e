#pragma once
// Nodes and background quadrature of an analytic solid (docs/meshless.md, "Nodes and quadrature").
//
// Octree, uniform at the node level: the bounding box is covered by cubic cells of edge h (the
// roots of a forest of octrees, one per cell; the grid starts at the box's lower corner and
// has ceil(extent / h) cells per axis). Nodes are placed per octant at the cells' corners that
// lie in the closed solid (d <= 1e-9 h), so the node spacing is h everywhere; adaptive node
// levels are not implemented.
//
// Quadrature: every cell is classified by the signed distance at its centre c and its
// half-diagonal r = sqrt(3) h / 2 (valid for the 1-Lipschitz distances of analytic_shape.hpp):
//   d(c) <= -r  wholly inside: the tensor Gauss-Legendre rule of `quadrature_order` points per
//               axis, kept whole;
//   d(c) >=  r  wholly outside: dropped;
//   otherwise   cut by the boundary: split into 8 octants, recursively, down to
//               `boundary_depth` levels below the cell; a cut leaf at that depth keeps the Gauss
//               points of its rule that are inside (d <= 0) with their full weights and drops
//               the others.
// The volume error is that of the dropped and kept parts of the cut leaves: at most about the
// cut leaves' volume, O(h 2^-depth); their errors have both signs and partly cancel, and the
// sphere's measured error falls faster (tests/forward/meshless/sampling_test.cpp, docs/meshless.md).
#include <Eigen/Core>
#include <vector>

#include "forward/meshless/analytic_shape.hpp"

namespace tailor {

struct OctreeSamplingOptions {
  double spacing = 0.0;       // h, the node spacing and root cell edge (> 0)
  int quadrature_order = 3;   // Gauss points per axis per leaf cell (1 to 8)
  int boundary_depth = 2;     // octree levels below a root cell for cells cut by the boundary (0 to 8)
};

struct OctreeSampling {
  Eigen::MatrixXd nodes;       // n x 3 rest positions
  Eigen::VectorXd spacing;     // per node: the node spacing h around it
  Eigen::MatrixXd points;      // quadrature points, q x 3
  Eigen::VectorXd weights;     // their weights (volume)
  int cells_inside = 0;        // root cells wholly inside
  int cells_cut = 0;           // root cells cut by the boundary
  int leaves_cut = 0;          // cut leaves at the deepest level (where points were dropped)
  double volume() const { return weights.sum(); }
};

// Gauss-Legendre points and weights on [-1, 1] (order 1 to 8).
void gauss_legendre(int order, std::vector<double>& points, std::vector<double>& weights);

// std::invalid_argument on a bad option or when no node lies inside the solid.
OctreeSampling sample_shape(const AnalyticShape& shape, const OctreeSamplingOptions& options);

}  // namespace tailor
