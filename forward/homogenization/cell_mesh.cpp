#include "forward/homogenization/cell_mesh.hpp"

#include <Eigen/LU>
#include <array>
#include <stdexcept>

#include "forward/mesh/generate.hpp"

namespace tailor {
namespace {

void check_lattice(double det, const char* who) {
  if (!(det > 0.0)) throw std::invalid_argument(std::string(who) + ": the lattice needs det A > 0");
}

}  // namespace

TriangleSplit parse_triangle_split(const std::string& name) {
  if (name == "forward") return TriangleSplit::forward;
  if (name == "backward") return TriangleSplit::backward;
  if (name == "crossed") return TriangleSplit::crossed;
  throw std::invalid_argument("unknown triangle split '" + name +
                              "' (expected forward, backward or crossed)");
}

Mesh lattice_triangle_mesh(const Eigen::Matrix2d& lattice, const Eigen::Vector2d& origin, int n1, int n2,
                           TriangleSplit split) {
  check_lattice(lattice.determinant(), "lattice_triangle_mesh");
  if (n1 <= 0 || n2 <= 0 || static_cast<long long>(n1) * n2 > 50'000'000LL)
    throw std::invalid_argument("lattice_triangle_mesh: grid counts must be positive (and not huge)");
  const int grid_vertices = (n1 + 1) * (n2 + 1);
  const int cells = n1 * n2;
  const bool crossed = split == TriangleSplit::crossed;
  Mesh mesh;
  mesh.rest_positions.resize(grid_vertices + (crossed ? cells : 0), 2);
  const auto vertex = [&](int i, int j) { return i + (n1 + 1) * j; };
  for (int j = 0; j <= n2; ++j)
    for (int i = 0; i <= n1; ++i) {
      const Eigen::Vector2d f(i == n1 ? 1.0 : double(i) / n1, j == n2 ? 1.0 : double(j) / n2);
      mesh.rest_positions.row(vertex(i, j)) = (origin + lattice * f).transpose();
    }
  mesh.elements.resize(crossed ? 4 * cells : 2 * cells, 3);
  int e = 0;
  for (int j = 0; j < n2; ++j)
    for (int i = 0; i < n1; ++i) {
      const int a = vertex(i, j), b = vertex(i + 1, j), c = vertex(i + 1, j + 1), d = vertex(i, j + 1);
      if (split == TriangleSplit::forward) {
        mesh.elements.row(e++) << a, b, c;
        mesh.elements.row(e++) << a, c, d;
      } else if (split == TriangleSplit::backward) {
        mesh.elements.row(e++) << a, b, d;
        mesh.elements.row(e++) << b, c, d;
      } else {
        const int m = grid_vertices + i + n1 * j;
        const Eigen::Vector2d f((i + 0.5) / n1, (j + 0.5) / n2);
        mesh.rest_positions.row(m) = (origin + lattice * f).transpose();
        mesh.elements.row(e++) << a, b, m;
        mesh.elements.row(e++) << b, c, m;
        mesh.elements.row(e++) << c, d, m;
        mesh.elements.row(e++) << d, a, m;
      }
    }
  mesh.element_regions = Eigen::VectorXi::Zero(mesh.num_elements());
  validate_mesh(mesh, "lattice_triangle_mesh");
  return mesh;
}

Mesh lattice_tet_mesh(const Eigen::Matrix3d& lattice, const Eigen::Vector3d& origin, int n1, int n2, int n3) {
  check_lattice(lattice.determinant(), "lattice_tet_mesh");
  Mesh mesh = box_tet_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), n1, n2, n3);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    mesh.rest_positions.row(v) = (origin + lattice * mesh.rest_positions.row(v).transpose()).transpose();
  mesh.element_regions = Eigen::VectorXi::Zero(mesh.num_elements());
  validate_mesh(mesh, "lattice_tet_mesh");
  return mesh;
}

}  // namespace tailor
