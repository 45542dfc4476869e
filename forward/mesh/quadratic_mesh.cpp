#include "forward/mesh/quadratic_mesh.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

namespace tailor {

template <>
const std::array<std::array<int, 2>, 1>& simplex_edges<1>() {
  static const std::array<std::array<int, 2>, 1> edges{{{0, 1}}};
  return edges;
}
template <>
const std::array<std::array<int, 2>, 3>& simplex_edges<2>() {
  static const std::array<std::array<int, 2>, 3> edges{{{0, 1}, {1, 2}, {2, 0}}};
  return edges;
}
template <>
const std::array<std::array<int, 2>, 6>& simplex_edges<3>() {
  static const std::array<std::array<int, 2>, 6> edges{{{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}}};
  return edges;
}

namespace {

// The local edges of a triangle or a tetrahedron, as pairs of local corners.
std::vector<std::array<int, 2>> quadratic_local_edges(int dim) {
  if (dim == 2) return {simplex_edges<2>().begin(), simplex_edges<2>().end()};
  return {simplex_edges<3>().begin(), simplex_edges<3>().end()};
}

std::pair<int, int> ordered_edge(int a, int b) { return a < b ? std::make_pair(a, b) : std::make_pair(b, a); }

}  // namespace

QuadraticMesh make_quadratic_mesh(const Mesh& linear) {
  validate_mesh(linear, "make_quadratic_mesh");
  const int dim = linear.dim();
  const auto local_edges = quadratic_local_edges(dim);
  const int per_element = static_cast<int>(local_edges.size());
  // Every element's edges, sorted and made unique: the edge index is the position in that list.
  std::vector<std::pair<int, int>> all;
  all.reserve(static_cast<std::size_t>(linear.num_elements()) * local_edges.size());
  for (int e = 0; e < linear.num_elements(); ++e)
    for (const auto& le : local_edges) all.push_back(ordered_edge(linear.elements(e, le[0]), linear.elements(e, le[1])));
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());

  QuadraticMesh q;
  q.corners = linear;
  const int corners = linear.num_vertices();
  const auto num_edges = static_cast<Eigen::Index>(all.size());
  q.edges.resize(num_edges, 2);
  q.rest_positions.resize(corners + num_edges, dim);
  q.rest_positions.topRows(corners) = linear.rest_positions;
  for (Eigen::Index i = 0; i < num_edges; ++i) {
    const auto [a, b] = all[static_cast<std::size_t>(i)];
    q.edges(i, 0) = a;
    q.edges(i, 1) = b;
    q.rest_positions.row(corners + i) = 0.5 * (linear.rest_positions.row(a) + linear.rest_positions.row(b));
  }
  q.elements.resize(linear.num_elements(), dim + 1 + per_element);
  for (int e = 0; e < linear.num_elements(); ++e) {
    for (int a = 0; a <= dim; ++a) q.elements(e, a) = linear.elements(e, a);
    for (int i = 0; i < per_element; ++i) {
      const auto& le = local_edges[static_cast<std::size_t>(i)];
      q.elements(e, dim + 1 + i) = edge_node(q, linear.elements(e, le[0]), linear.elements(e, le[1]));
    }
  }
  return q;
}

int edge_node(const QuadraticMesh& mesh, int a, int b) {
  const auto [lo, hi] = ordered_edge(a, b);
  // edges is sorted lexicographically: binary search on (lo, hi).
  Eigen::Index first = 0, last = mesh.edges.rows();
  while (first < last) {
    const Eigen::Index mid = first + (last - first) / 2;
    const std::pair<int, int> at(mesh.edges(mid, 0), mesh.edges(mid, 1));
    if (at < std::make_pair(lo, hi))
      first = mid + 1;
    else
      last = mid;
  }
  if (first < mesh.edges.rows() && mesh.edges(first, 0) == lo && mesh.edges(first, 1) == hi)
    return mesh.num_corners() + static_cast<int>(first);
  return -1;
}

Eigen::MatrixXi quadratic_facets(const QuadraticMesh& mesh, const Eigen::MatrixXi& facets) {
  const int dim = mesh.dim();
  if (facets.rows() > 0 && facets.cols() != dim)
    throw std::invalid_argument("quadratic_facets: facets must have dim corner vertices");
  const int edges_per_facet = dim == 2 ? 1 : 3;
  Eigen::MatrixXi out(facets.rows(), dim + edges_per_facet);
  for (Eigen::Index k = 0; k < facets.rows(); ++k) {
    out.row(k).head(dim) = facets.row(k);
    for (int i = 0; i < edges_per_facet; ++i) {
      // 2D: edge (0, 1); 3D: edges (0,1), (1,2), (2,0), the triangle's own order.
      const int a = facets(k, i), b = facets(k, (i + 1) % dim);
      const int node = edge_node(mesh, a, b);
      if (node < 0)
        throw std::invalid_argument("quadratic_facets: facet " + std::to_string(k) + " has an edge (" +
                                    std::to_string(a) + ", " + std::to_string(b) + ") that is not in the mesh");
      out(k, dim + i) = node;
    }
  }
  return out;
}

std::vector<int> nodes_where(const QuadraticMesh& mesh, const std::function<bool(const Eigen::VectorXd&)>& on) {
  std::vector<int> nodes;
  for (int v = 0; v < mesh.num_nodes(); ++v)
    if (on(mesh.rest_positions.row(v).transpose())) nodes.push_back(v);
  return nodes;
}

std::vector<int> node_dofs(const QuadraticMesh& mesh, const std::vector<int>& nodes) {
  std::vector<int> dofs;
  dofs.reserve(nodes.size() * static_cast<std::size_t>(mesh.dim()));
  for (int v : nodes)
    for (int i = 0; i < mesh.dim(); ++i) dofs.push_back(mesh.dim() * v + i);
  return dofs;
}

Eigen::VectorXd extend_corner_field(const QuadraticMesh& mesh, const Eigen::VectorXd& corner_field) {
  const int dim = mesh.dim();
  if (corner_field.size() != static_cast<Eigen::Index>(dim) * mesh.num_corners())
    throw std::invalid_argument("extend_corner_field: the field needs dim values per corner vertex");
  Eigen::VectorXd out(static_cast<Eigen::Index>(dim) * mesh.num_nodes());
  out.head(corner_field.size()) = corner_field;
  for (Eigen::Index i = 0; i < mesh.edges.rows(); ++i)
    out.segment(dim * (mesh.num_corners() + i), dim) =
        0.5 * (corner_field.segment(dim * mesh.edges(i, 0), dim) + corner_field.segment(dim * mesh.edges(i, 1), dim));
  return out;
}

Eigen::VectorXd quadratic_rest_state(const QuadraticMesh& mesh) {
  const int dim = mesh.dim();
  Eigen::VectorXd x(static_cast<Eigen::Index>(dim) * mesh.num_nodes());
  for (int v = 0; v < mesh.num_nodes(); ++v) x.segment(dim * v, dim) = mesh.rest_positions.row(v).transpose();
  return x;
}

}  // namespace tailor
