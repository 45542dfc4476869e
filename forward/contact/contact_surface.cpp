// Edges of a triangle surface and input checks (see contact_surface.hpp).
#include "forward/contact/contact_surface.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

namespace tailor::contact {

ContactSurface ContactSurface::from_faces(int num_vertices, Eigen::MatrixX3i faces, std::vector<int> groups,
                                          const Eigen::MatrixX2i& extra_edges) {
  if (num_vertices < 0) throw std::invalid_argument("ContactSurface: negative vertex count");
  if (!groups.empty() && static_cast<int>(groups.size()) != num_vertices)
    throw std::invalid_argument("ContactSurface: " + std::to_string(groups.size()) + " groups for " +
                                std::to_string(num_vertices) + " vertices");
  auto check = [&](int v, const char* what, int row) {
    if (v < 0 || v >= num_vertices)
      throw std::invalid_argument(std::string("ContactSurface: ") + what + " " + std::to_string(row) +
                                  " refers to vertex " + std::to_string(v) + " of " +
                                  std::to_string(num_vertices));
  };
  std::vector<std::pair<int, int>> edges;
  for (int f = 0; f < faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) check(faces(f, k), "face", f);
    if (faces(f, 0) == faces(f, 1) || faces(f, 1) == faces(f, 2) || faces(f, 2) == faces(f, 0))
      throw std::invalid_argument("ContactSurface: face " + std::to_string(f) + " repeats a vertex");
    for (int k = 0; k < 3; ++k) {
      const int a = faces(f, k), b = faces(f, (k + 1) % 3);
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  for (int e = 0; e < extra_edges.rows(); ++e) {
    check(extra_edges(e, 0), "edge", e);
    check(extra_edges(e, 1), "edge", e);
    if (extra_edges(e, 0) == extra_edges(e, 1))
      throw std::invalid_argument("ContactSurface: edge " + std::to_string(e) + " repeats a vertex");
    edges.emplace_back(std::min(extra_edges(e, 0), extra_edges(e, 1)),
                       std::max(extra_edges(e, 0), extra_edges(e, 1)));
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  ContactSurface s;
  s.num_vertices = num_vertices;
  s.faces = std::move(faces);
  s.edges.resize(static_cast<Eigen::Index>(edges.size()), 2);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    s.edges(static_cast<Eigen::Index>(e), 0) = edges[e].first;
    s.edges(static_cast<Eigen::Index>(e), 1) = edges[e].second;
  }
  s.groups = std::move(groups);
  return s;
}

}  // namespace tailor::contact
