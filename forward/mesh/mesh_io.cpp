// Dispatch of read_mesh on the file extension, and the last step shared by all readers.
#include "forward/mesh/mesh_io.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "forward/mesh/text_scanner_detail.hpp"

namespace tailor {
namespace mesh_detail {

void flatten_triangles(RawMesh& raw, const std::string& path) {
  const std::size_t num_vertices = raw.coordinates.size() / 3;
  std::vector<char> used(num_vertices, 0);
  for (const int v : raw.elements) used[static_cast<std::size_t>(v)] = 1;

  // The plane's height is taken from the first used vertex; the tolerance is relative to
  // the extent of the mesh so that rounding in the file does not matter.
  double extent = 0.0;
  std::size_t reference = num_vertices;
  for (std::size_t v = 0; v < num_vertices; ++v) {
    if (!used[v]) continue;
    if (reference == num_vertices) reference = v;
    for (int k = 0; k < 3; ++k) {
      extent = std::max(extent, std::abs(raw.coordinates[3 * v + k] - raw.coordinates[3 * reference + k]));
    }
  }
  const double tolerance = 1e-9 * extent;
  for (std::size_t v = 0; v < num_vertices; ++v) {
    if (!used[v]) continue;
    const double z = raw.coordinates[3 * v + 2];
    const double z0 = raw.coordinates[3 * reference + 2];
    if (std::abs(z - z0) > tolerance) {
      char heights[96];
      std::snprintf(heights, sizeof heights, "vertex %zu has z = %.6g, vertex %zu has z = %.6g", v, z,
                    reference, z0);
      throw MeshError(path +
                      ": the file has triangles but no tetrahedra, so it is read as a 2D mesh, "
                      "but its triangles are not in one plane z = const (" +
                      heights + ", counting vertices from 0 in file order)");
    }
  }
  std::vector<double> planar;
  planar.reserve(num_vertices * 2);
  for (std::size_t v = 0; v < num_vertices; ++v) {
    planar.push_back(raw.coordinates[3 * v]);
    planar.push_back(raw.coordinates[3 * v + 1]);
  }
  raw.coordinates = std::move(planar);
  raw.dim = 2;
}

void set_elements_from_numbers(RawMesh& raw, const std::vector<std::int64_t>& numbers,
                               int vertices_per_element, int base, const std::string& path) {
  const auto num_vertices = static_cast<std::int64_t>(raw.coordinates.size() / raw.dim);
  raw.elements.resize(numbers.size());
  for (std::size_t i = 0; i < numbers.size(); ++i) {
    const std::int64_t index = numbers[i] - base;
    if (index < 0 || index >= num_vertices) {
      const std::size_t e = i / static_cast<std::size_t>(vertices_per_element);
      throw MeshError(path + ":" + std::to_string(raw.element_lines[e]) + ": element " +
                      std::to_string(e + static_cast<std::size_t>(base)) + " references vertex " +
                      std::to_string(numbers[i]) + ", but only " + std::to_string(num_vertices) +
                      " vertices are defined (numbered from " + std::to_string(base) + ")");
    }
    raw.elements[i] = static_cast<int>(index);
  }
}

Mesh finish_mesh(const RawMesh& raw, const std::string& path) {
  const int dim = raw.dim;
  const auto num_vertices = static_cast<Eigen::Index>(raw.coordinates.size() / dim);
  const auto num_elements = static_cast<Eigen::Index>(raw.regions.size());
  Mesh mesh;
  // The raw arrays are row-major; copy through row-major maps into Eigen's column-major.
  mesh.rest_positions =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
          raw.coordinates.data(), num_vertices, dim);
  mesh.elements = Eigen::Map<const Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      raw.elements.data(), num_elements, dim + 1);
  mesh.element_regions = Eigen::Map<const Eigen::VectorXi>(raw.regions.data(), num_elements);
  validate_mesh_with_lines(mesh, path, &raw.element_lines);
  return mesh;
}

}  // namespace mesh_detail

Mesh read_mesh(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".msh") return read_gmsh(path);
  if (extension == ".mesh") return read_medit(path);
  if (extension == ".node" || extension == ".ele") return read_tetgen(path);
  // A TetGen base name ("cube" or "cube.1" for cube.1.node) has no known extension.
  if (std::filesystem::exists(path + ".node")) return read_tetgen(path);
  throw MeshError(path + ": unknown mesh file extension '" + extension +
                  "' (expected .msh, .mesh, .node or .ele)");
}

}  // namespace tailor
