#pragma once
// Structured meshes of one parallelepiped cell Y = { origin + A f : f in [0, 1]^dim } (lattice
// vectors as the columns of A, det A > 0), periodic by construction: the grid in fractional
// coordinates is mapped by A, so opposite faces carry translated copies of the same vertices.
#include <string>

#include "forward/mesh/mesh.hpp"

namespace tailor {

// How each grid parallelogram of a 2D cell is split into triangles.
enum class TriangleSplit {
  forward,   // 2 triangles along the diagonal (i, j)-(i+1, j+1)
  backward,  // 2 triangles along the diagonal (i+1, j)-(i, j+1) (equilateral on a 60-degree lattice)
  crossed,   // 4 triangles meeting at the parallelogram's centre (mirror-symmetric pattern)
};
TriangleSplit parse_triangle_split(const std::string& name);  // throws std::invalid_argument

// n1 x n2 grid parallelograms. Grid vertex (i, j) has index i + (n1 + 1) j; crossed centres
// follow, one per parallelogram. Throws std::invalid_argument for non-positive counts or det A <= 0.
Mesh lattice_triangle_mesh(const Eigen::Matrix2d& lattice, const Eigen::Vector2d& origin, int n1, int n2,
                           TriangleSplit split = TriangleSplit::forward);
// n1 x n2 x n3 grid parallelepipeds of 6 Kuhn tetrahedra each (box_tet_mesh of the unit cube
// mapped by A).
Mesh lattice_tet_mesh(const Eigen::Matrix3d& lattice, const Eigen::Vector3d& origin, int n1, int n2, int n3);

}  // namespace tailor
