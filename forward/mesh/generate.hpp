#pragma once
// Structured mesh generators.
#include "forward/mesh/mesh.hpp"

namespace tailor {

// Box [lo, hi] split into nx * ny * nz cubes of 6 positively oriented tetrahedra each
// (Kuhn / Freudenthal split, conforming across cells). Vertex (i, j, k) has index
// i + (nx + 1) * (j + (ny + 1) * k).
Mesh box_tet_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int nx, int ny, int nz);
// Rectangle [lo, hi] split into nx * ny squares of 2 positively oriented triangles each.
// Vertex (i, j) has index i + (nx + 1) * j.
Mesh rectangle_triangle_mesh(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, int nx, int ny);

}  // namespace tailor
