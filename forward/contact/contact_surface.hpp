#pragma once
// ContactSurface: the triangles, edges and vertices that take part in contact, in surface
// vertex indices 0..num_vertices-1 (the caller maps them to DOFs or to rigid bodies).
//
// Groups: optional, one per surface vertex; pairs whose vertices all lie in one group are
// never candidates (the vertices of one rigid body cannot approach each other). Pairs that
// share a vertex (a vertex and its own triangle, adjacent edges) are never candidates.
#include <Eigen/Core>
#include <vector>

namespace tailor::contact {

struct ContactSurface {
  int num_vertices = 0;
  Eigen::MatrixX3i faces;   // triangles (may be empty: edges and vertices only, e.g. rods)
  Eigen::MatrixX2i edges;   // unique undirected edges
  std::vector<int> groups;  // empty, or one group id per vertex

  // The edges of `faces` (each undirected edge once) plus `extra_edges`. Throws
  // std::invalid_argument on indices out of range, degenerate faces or a wrong group size.
  static ContactSurface from_faces(int num_vertices, Eigen::MatrixX3i faces, std::vector<int> groups = {},
                                   const Eigen::MatrixX2i& extra_edges = Eigen::MatrixX2i(0, 2));
  int group(int v) const { return groups.empty() ? 0 : groups[static_cast<std::size_t>(v)]; }
  bool grouped() const { return !groups.empty(); }
};

// Surface positions, one row per surface vertex [length].
using Positions = Eigen::Matrix<double, Eigen::Dynamic, 3>;

}  // namespace tailor::contact
