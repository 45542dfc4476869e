#include "forward/mesh/mesh.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "forward/core/format_number.hpp"
#include "forward/mesh/text_scanner_detail.hpp"

namespace tailor {
namespace {

// Signed volume (area in 2D) of element e; indices must be valid.
double signed_volume(const Mesh& mesh, int e) {
  const auto& x = mesh.rest_positions;
  const auto& t = mesh.elements;
  if (mesh.dim() == 3) {
    const Eigen::Vector3d a = x.row(t(e, 0)).transpose();
    const Eigen::Vector3d ab = x.row(t(e, 1)).transpose() - a;
    const Eigen::Vector3d ac = x.row(t(e, 2)).transpose() - a;
    const Eigen::Vector3d ad = x.row(t(e, 3)).transpose() - a;
    return ab.cross(ac).dot(ad) / 6.0;
  }
  const Eigen::Vector2d a = x.row(t(e, 0)).transpose();
  const Eigen::Vector2d ab = x.row(t(e, 1)).transpose() - a;
  const Eigen::Vector2d ac = x.row(t(e, 2)).transpose() - a;
  return (ab.x() * ac.y() - ab.y() * ac.x()) / 2.0;
}

double longest_edge(const Mesh& mesh, int e) {
  const int n = static_cast<int>(mesh.elements.cols());
  double longest = 0.0;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const double length =
          (mesh.rest_positions.row(mesh.elements(e, i)) - mesh.rest_positions.row(mesh.elements(e, j)))
              .norm();
      longest = std::max(longest, length);
    }
  }
  return longest;
}

void check_shape(const Mesh& mesh, const std::string& source) {
  const int dim = mesh.dim();
  if (dim != 2 && dim != 3) {
    throw MeshError(source + ": rest positions have " + std::to_string(dim) +
                    " columns; a mesh must be 2D (triangles) or 3D (tetrahedra)");
  }
  if (mesh.elements.cols() != dim + 1) {
    throw MeshError(source + ": elements have " + std::to_string(mesh.elements.cols()) +
                    " vertices each, but a " + std::to_string(dim) + "D mesh needs " +
                    std::to_string(dim + 1));
  }
}

// Local facets of a positively oriented simplex, ordered so that their normals point out
// of it: for a tetrahedron (q - p) x (r - p) of facet (p, q, r); for a triangle the edge
// (p, q) of a counter-clockwise boundary, whose outward normal is (q - p) turned clockwise.
constexpr int kTetFacets[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
constexpr int kTriangleFacets[3][2] = {{0, 1}, {1, 2}, {2, 0}};

struct FacetRecord {
  std::array<int, 3> key;  // sorted vertex indices (the third is -1 for edges)
  int element;
  int local;  // which facet of the element
};

// All element facets, sorted so that copies of the same facet are adjacent. Sorting keeps
// this O(m log m) and cache-friendly on large meshes, unlike a map of facets.
std::vector<FacetRecord> sorted_facets(const Mesh& mesh) {
  const int dim = mesh.dim();
  if ((dim != 2 && dim != 3) || mesh.elements.cols() != dim + 1) {
    throw std::invalid_argument("mesh facets: elements must have dim + 1 vertices, dim 2 or 3");
  }
  const int facets_per_element = dim + 1;
  std::vector<FacetRecord> facets;
  facets.reserve(static_cast<std::size_t>(mesh.num_elements()) * facets_per_element);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    for (int f = 0; f < facets_per_element; ++f) {
      FacetRecord record{{-1, -1, -1}, e, f};
      for (int k = 0; k < dim; ++k) {
        const int local_vertex = dim == 3 ? kTetFacets[f][k] : kTriangleFacets[f][k];
        record.key[k] = mesh.elements(e, local_vertex);
      }
      // Three compare-and-swaps sort the key (the unused third entry of an edge is -1 and
      // must stay last, so edges only need the first).
      if (record.key[0] > record.key[1]) std::swap(record.key[0], record.key[1]);
      if (dim == 3) {
        if (record.key[1] > record.key[2]) std::swap(record.key[1], record.key[2]);
        if (record.key[0] > record.key[1]) std::swap(record.key[0], record.key[1]);
      }
      facets.push_back(record);
    }
  }
  std::sort(facets.begin(), facets.end(), [](const FacetRecord& a, const FacetRecord& b) {
    return a.key != b.key ? a.key < b.key : a.element < b.element;
  });
  return facets;
}

// Calls visit(first, last) for each run [first, last) of records sharing a facet.
template <class Visit>
void for_each_facet_run(const std::vector<FacetRecord>& facets, Visit visit) {
  std::size_t first = 0;
  while (first < facets.size()) {
    std::size_t last = first + 1;
    while (last < facets.size() && facets[last].key == facets[first].key) ++last;
    visit(first, last);
    first = last;
  }
}

}  // namespace

namespace mesh_detail {

void validate_mesh_with_lines(const Mesh& mesh, const std::string& source,
                              const std::vector<int>* element_lines) {
  check_shape(mesh, source);
  const int dim = mesh.dim();
  const int num_vertices = mesh.num_vertices();
  const int num_elements = mesh.num_elements();
  if (num_elements == 0) throw MeshError(source + ": the mesh has no elements");
  if (mesh.element_regions.size() != num_elements) {
    throw MeshError(source + ": " + std::to_string(mesh.element_regions.size()) + " element regions for " +
                    std::to_string(num_elements) + " elements");
  }
  const bool have_lines =
      element_lines != nullptr && element_lines->size() == static_cast<std::size_t>(num_elements);
  const auto where = [&](int e) {
    return have_lines ? source + ":" + std::to_string((*element_lines)[e]) : source;
  };
  // Files number elements their own way (tags, 1-based); with a line to point at, say
  // plainly that the index is the mesh's.
  const auto element = [&](int e) {
    return "element " + std::to_string(e) + (have_lines ? " (0-based)" : "");
  };

  for (int v = 0; v < num_vertices; ++v) {
    for (int k = 0; k < dim; ++k) {
      if (!std::isfinite(mesh.rest_positions(v, k))) {
        throw MeshError(source + ": vertex " + std::to_string(v) + " has a non-finite coordinate (" +
                        format_number(mesh.rest_positions(v, k)) + ")");
      }
    }
  }
  for (int e = 0; e < num_elements; ++e) {
    for (int k = 0; k <= dim; ++k) {
      const int v = mesh.elements(e, k);
      if (v < 0 || v >= num_vertices) {
        throw MeshError(where(e) + ": " + element(e) + " references vertex " + std::to_string(v) +
                        ", but only " + std::to_string(num_vertices) + " vertices are defined");
      }
    }
  }
  for (int e = 0; e < num_elements; ++e) {
    const double volume = signed_volume(mesh, e);
    const double longest = longest_edge(mesh, e);
    // Relative to the element's own size, so that the test does not depend on units.
    const double tolerance = 1e-12 * std::pow(longest, dim);
    if (volume > tolerance) continue;
    const char* measure = dim == 3 ? "volume" : "area";
    std::string vertices;
    if (!have_lines) {
      vertices = "; vertices";
      for (int k = 0; k <= dim; ++k) {
        vertices += ' ';
        vertices += std::to_string(mesh.elements(e, k));
      }
    }
    if (volume < -tolerance) {
      throw MeshError(where(e) + ": " + element(e) + " is inverted (signed " + measure + " " +
                      format_number(volume) + vertices +
                      "); list its vertices in positive order, e.g. swap the last two");
    }
    throw MeshError(where(e) + ": " + element(e) + " is degenerate (signed " + measure + " " +
                    format_number(volume) + ", longest edge " + format_number(longest) + vertices + ")");
  }
  // A vertex no element uses has no stiffness and no mass: the system is singular there (Newton
  // takes extra iterations, eigensolvers and periodic solves fail without saying why). Refused,
  // naming the vertices, rather than dropped: dropping would renumber the vertices that scenes
  // select by index.
  std::vector<char> used(static_cast<std::size_t>(num_vertices), 0);
  for (int e = 0; e < num_elements; ++e)
    for (int k = 0; k <= dim; ++k) used[static_cast<std::size_t>(mesh.elements(e, k))] = 1;
  if (const long unused = std::count(used.begin(), used.end(), 0); unused > 0) {
    std::string listed;
    int shown = 0;
    for (int v = 0; v < num_vertices && shown < 5; ++v)
      if (!used[static_cast<std::size_t>(v)]) listed += (shown++ ? ", " : "") + std::to_string(v);
    if (unused > shown) listed += ", ...";
    throw MeshError(source + ": " + std::to_string(unused) + " of " + std::to_string(num_vertices) +
                    " vertices are used by no element (0-based: " + listed +
                    "); a free vertex has no stiffness or mass. Remove them from the mesh (e.g. "
                    "geometry points saved with it)");
  }
}

}  // namespace mesh_detail

void validate_mesh(const Mesh& mesh, const std::string& source) {
  mesh_detail::validate_mesh_with_lines(mesh, source, nullptr);
}

Eigen::VectorXd element_volumes(const Mesh& mesh) {
  const int dim = mesh.dim();
  if ((dim != 2 && dim != 3) || mesh.elements.cols() != dim + 1) {
    throw std::invalid_argument("element_volumes: elements must have dim + 1 vertices, dim 2 or 3");
  }
  if (mesh.num_elements() > 0 &&
      (mesh.elements.minCoeff() < 0 || mesh.elements.maxCoeff() >= mesh.num_vertices())) {
    throw std::out_of_range("element_volumes: an element references a vertex out of range");
  }
  Eigen::VectorXd volumes(mesh.num_elements());
  for (int e = 0; e < mesh.num_elements(); ++e) volumes[e] = signed_volume(mesh, e);
  return volumes;
}

Eigen::MatrixXi boundary_facets(const Mesh& mesh, Eigen::VectorXi* owner) {
  const std::vector<FacetRecord> facets = sorted_facets(mesh);
  std::vector<std::pair<int, int>> boundary;  // (element, local facet)
  for_each_facet_run(facets, [&](std::size_t first, std::size_t last) {
    if (last - first == 1) boundary.emplace_back(facets[first].element, facets[first].local);
  });
  // Element order keeps the output deterministic and close to the element numbering.
  std::sort(boundary.begin(), boundary.end());

  const int dim = mesh.dim();
  Eigen::MatrixXi result(static_cast<Eigen::Index>(boundary.size()), dim);
  if (owner != nullptr) owner->resize(static_cast<Eigen::Index>(boundary.size()));
  for (std::size_t i = 0; i < boundary.size(); ++i) {
    const auto [element, local] = boundary[i];
    for (int k = 0; k < dim; ++k) {
      const int local_vertex = dim == 3 ? kTetFacets[local][k] : kTriangleFacets[local][k];
      result(static_cast<Eigen::Index>(i), k) = mesh.elements(element, local_vertex);
    }
    if (owner != nullptr) (*owner)[static_cast<Eigen::Index>(i)] = element;
  }
  return result;
}

Eigen::MatrixXi element_adjacency(const Mesh& mesh) {
  const std::vector<FacetRecord> facets = sorted_facets(mesh);
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(facets.size() / 2);
  for_each_facet_run(facets, [&](std::size_t first, std::size_t last) {
    // Runs are sorted by element; a facet shared by more than two elements (non-manifold
    // input) links every pair of them.
    for (std::size_t i = first; i < last; ++i) {
      for (std::size_t j = i + 1; j < last; ++j) {
        if (facets[i].element != facets[j].element) {
          pairs.emplace_back(facets[i].element, facets[j].element);
        }
      }
    }
  });
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  Eigen::MatrixXi result(static_cast<Eigen::Index>(pairs.size()), 2);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    result(static_cast<Eigen::Index>(i), 0) = pairs[i].first;
    result(static_cast<Eigen::Index>(i), 1) = pairs[i].second;
  }
  return result;
}

}  // namespace tailor
