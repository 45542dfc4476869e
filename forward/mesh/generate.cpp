#include "forward/mesh/generate.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <stdexcept>
#include <string>

namespace tailor {
namespace {

void check_counts(std::initializer_list<int> counts, std::int64_t num_vertices, std::int64_t num_elements,
                  const char* who) {
  for (const int n : counts) {
    if (n <= 0)
      throw std::invalid_argument(std::string(who) + ": cell counts must be positive, got " +
                                  std::to_string(n));
  }
  constexpr std::int64_t kMaxIndex = std::numeric_limits<int>::max();
  if (num_vertices > kMaxIndex || num_elements > kMaxIndex) {
    throw std::invalid_argument(std::string(who) + ": too many cells for int indices");
  }
}

template <class Vec>
void check_box(const Vec& lo, const Vec& hi, const char* who) {
  for (int k = 0; k < lo.size(); ++k) {
    // Written so that NaN bounds fail too.
    if (!(lo[k] < hi[k]) || !std::isfinite(lo[k]) || !std::isfinite(hi[k])) {
      throw std::invalid_argument(std::string(who) + ": need finite lo < hi in every coordinate, got lo[" +
                                  std::to_string(k) + "] = " + std::to_string(lo[k]) + ", hi[" +
                                  std::to_string(k) + "] = " + std::to_string(hi[k]));
    }
  }
}

// The six Kuhn tetrahedra of the unit cube: each walks from corner (0,0,0) to (1,1,1) along
// the axes in one order, so every cell is split along the same main diagonal and the split
// faces of neighbouring cells match. Corners are bit-coded x + 2y + 4z. For odd axis orders
// the walk is negatively oriented, so its middle two corners are swapped.
constexpr std::array<std::array<int, 4>, 6> kKuhnTets = {{
    {0, 1, 3, 7},  // x, y, z
    {0, 2, 6, 7},  // y, z, x
    {0, 4, 5, 7},  // z, x, y
    {0, 5, 1, 7},  // x, z, y (odd: the walk is 0, 1, 5, 7)
    {0, 3, 2, 7},  // y, x, z (odd: the walk is 0, 2, 3, 7)
    {0, 6, 4, 7},  // z, y, x (odd: the walk is 0, 4, 6, 7)
}};

}  // namespace

Mesh box_tet_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int nx, int ny, int nz) {
  check_box(lo, hi, "box_tet_mesh");
  const std::int64_t num_vertices = (std::int64_t{nx} + 1) * (std::int64_t{ny} + 1) * (std::int64_t{nz} + 1);
  const std::int64_t num_cells = std::int64_t{nx} * ny * nz;
  check_counts({nx, ny, nz}, num_vertices, 6 * num_cells, "box_tet_mesh");

  Mesh mesh;
  mesh.rest_positions.resize(num_vertices, 3);
  const auto vertex = [&](int i, int j, int k) { return i + (nx + 1) * (j + (ny + 1) * k); };
  const Eigen::Vector3d step = (hi - lo).cwiseQuotient(Eigen::Vector3d(nx, ny, nz));
  for (int k = 0; k <= nz; ++k) {
    for (int j = 0; j <= ny; ++j) {
      for (int i = 0; i <= nx; ++i) {
        // The far faces get exactly hi, not lo + n * step, which may round differently.
        mesh.rest_positions(vertex(i, j, k), 0) = i == nx ? hi.x() : lo.x() + i * step.x();
        mesh.rest_positions(vertex(i, j, k), 1) = j == ny ? hi.y() : lo.y() + j * step.y();
        mesh.rest_positions(vertex(i, j, k), 2) = k == nz ? hi.z() : lo.z() + k * step.z();
      }
    }
  }
  mesh.elements.resize(6 * num_cells, 4);
  int e = 0;
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        std::array<int, 8> corner;
        for (int c = 0; c < 8; ++c) corner[c] = vertex(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
        for (const auto& tet : kKuhnTets) {
          for (int a = 0; a < 4; ++a) mesh.elements(e, a) = corner[tet[a]];
          ++e;
        }
      }
    }
  }
  mesh.element_regions = Eigen::VectorXi::Zero(mesh.elements.rows());
  return mesh;
}

Mesh rectangle_triangle_mesh(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, int nx, int ny) {
  check_box(lo, hi, "rectangle_triangle_mesh");
  const std::int64_t num_vertices = (std::int64_t{nx} + 1) * (std::int64_t{ny} + 1);
  const std::int64_t num_cells = std::int64_t{nx} * ny;
  check_counts({nx, ny}, num_vertices, 2 * num_cells, "rectangle_triangle_mesh");

  Mesh mesh;
  mesh.rest_positions.resize(num_vertices, 2);
  const auto vertex = [&](int i, int j) { return i + (nx + 1) * j; };
  const Eigen::Vector2d step = (hi - lo).cwiseQuotient(Eigen::Vector2d(nx, ny));
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      mesh.rest_positions(vertex(i, j), 0) = i == nx ? hi.x() : lo.x() + i * step.x();
      mesh.rest_positions(vertex(i, j), 1) = j == ny ? hi.y() : lo.y() + j * step.y();
    }
  }
  mesh.elements.resize(2 * num_cells, 3);
  int e = 0;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      // Both triangles counter-clockwise, split along the diagonal (i, j)-(i+1, j+1).
      mesh.elements.row(e++) << vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1);
      mesh.elements.row(e++) << vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1);
    }
  }
  mesh.element_regions = Eigen::VectorXi::Zero(mesh.elements.rows());
  return mesh;
}

}  // namespace tailor
