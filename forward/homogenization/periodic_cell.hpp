#pragma once
// Periodic unit cells: a simplicial mesh of one parallelepiped cell
//   Y = { origin + A f : f in [0, 1]^dim },  A = [a_1 ... a_dim] (lattice vectors as columns),
// whose boundary vertices pair up under the lattice translations a_k. Pairing is automatic:
// every vertex is mapped to fractional coordinates f = A^-1 (X - origin), wrapped into [0, 1),
// and vertices with the same wrapped coordinates (within a tolerance) are copies of one
// periodic node. See docs/homogenization.md.
#include <Eigen/LU>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "forward/core/elimination.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor {

// The mesh is not periodic under the given lattice (unmatched boundary vertices, vertices
// outside the cell, volume that does not tile the cell).
class PeriodicityError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct PeriodicCell {
  Mesh mesh;
  Eigen::MatrixXd lattice;  // dim x dim, column k = lattice vector a_k (same length unit as the mesh)
  Eigen::VectorXd origin;   // dim; corner of the cell
  std::vector<int> master;  // per vertex: the representative vertex of its periodic node
  int anchor = 0;           // a master vertex whose fluctuation is fixed (removes rigid translation)
  // Which lattice directions are periodic (all by default). A plate-like cell is periodic along
  // a_1, a_2 only; its third "lattice vector" spans the thickness (free faces).
  std::vector<bool> periodic;

  int dim() const { return mesh.dim(); }
  double volume() const { return std::abs(lattice.determinant()); }  // |det A| (area in 2D)
  int num_periodic_nodes() const;                                    // number of distinct masters
};

// Pairs the vertices of `mesh` under the lattice. `tolerance` is relative to the cell size
// (max lattice vector length): fractional coordinates within tolerance of 0 or 1 are on the
// boundary. Throws PeriodicityError naming up to 10 unmatched vertices (index and position),
// when a vertex lies outside the cell, or when the element volumes do not sum to |det A|;
// std::invalid_argument for a lattice of the wrong size or with det A <= 0.
PeriodicCell make_periodic_cell(const Mesh& mesh, const Eigen::MatrixXd& lattice,
                                const Eigen::VectorXd& origin, double tolerance = 1e-8);
// A cell periodic only along the lattice vectors k with periodic[k] (a plate: {true, true,
// false}); the other faces are free and their vertices need no images.
PeriodicCell make_periodic_cell(const Mesh& mesh, const Eigen::MatrixXd& lattice,
                                const Eigen::VectorXd& origin, double tolerance,
                                const std::vector<bool>& periodic);
// Same with the lattice of the mesh's axis-aligned bounding box (a box cell).
PeriodicCell make_box_periodic_cell(const Mesh& mesh, double tolerance = 1e-8);

// Periodic fluctuation with an imposed affine part, as an elimination of the position DOFs
// (x[dim * v + k], world positions):
//   x_v = X_v + H X_v + w_{master(v)},   w_anchor = 0,
// i.e. x = x0 + S y with x0 = (I + H) X (the macro displacement gradient H applied to rest
// positions) and y the fluctuation of every master except the anchor. The offset for another
// H is macro_offset(); S does not change.
Elimination periodic_elimination(const PeriodicCell& cell, const Eigen::MatrixXd& macro_gradient);
Vector macro_offset(const PeriodicCell& cell, const Eigen::MatrixXd& macro_gradient);

}  // namespace tailor
