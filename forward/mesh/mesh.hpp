#pragma once
// Simplicial meshes: tetrahedra in 3D, triangles in 2D.
//
// Conventions (libigl-like): rest_positions is num_vertices x dim (one row per vertex),
// elements is num_elements x (dim + 1) with 0-based vertex indices. A tetrahedron (a, b, c, d)
// is positively oriented when (b - a) x (c - a) . (d - a) > 0; a triangle (a, b, c) when
// (b - a) x (c - a) > 0.
#include <Eigen/Core>
#include <functional>
#include <stdexcept>
#include <string>

namespace tailor {

struct Mesh {
  Eigen::MatrixXd rest_positions;   // num_vertices x dim
  Eigen::MatrixXi elements;         // num_elements x (dim + 1)
  Eigen::VectorXi element_regions;  // num_elements; region / physical tag, 0 when none given

  int dim() const { return static_cast<int>(rest_positions.cols()); }
  int num_vertices() const { return static_cast<int>(rest_positions.rows()); }
  int num_elements() const { return static_cast<int>(elements.rows()); }
};

// Any problem with mesh input: the message names the file (or "generated mesh"), the line
// or element, and what is wrong.
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Checks sizes, index ranges, finite coordinates, and that no element is degenerate or
// inverted at rest (signed volume > tolerance * (element edge length)^dim). `source` names the
// origin in messages. Throws MeshError.
void validate_mesh(const Mesh& mesh, const std::string& source);

// Signed rest volume (area in 2D) of every element.
Eigen::VectorXd element_volumes(const Mesh& mesh);

// Boundary facets (triangles of tets, edges of triangles), num_facets x dim, ordered so the
// facet normal points out of the mesh. Also returns the owning element of each facet.
Eigen::MatrixXi boundary_facets(const Mesh& mesh, Eigen::VectorXi* owner = nullptr);

// The boundary facets all of whose vertices satisfy `on` (a predicate on rest positions),
// oriented as boundary_facets(); e.g. the end face x = L of a bar for a traction.
Eigen::MatrixXi boundary_facets_where(const Mesh& mesh, const std::function<bool(const Eigen::VectorXd&)>& on);

// Element adjacency through shared facets: pairs (e, f) with e < f.
Eigen::MatrixXi element_adjacency(const Mesh& mesh);

}  // namespace tailor
