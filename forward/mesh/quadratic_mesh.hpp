#pragma once
// Quadratic (P2) simplicial meshes built from linear ones: 6-node triangles in 2D and 10-node
// tetrahedra in 3D, one node at every corner and one on every edge. The edge nodes start at the
// edge midpoints and may be moved afterwards (e.g. onto a curved boundary): the elements are
// isoparametric, their geometry is interpolated from all their nodes.
//
// Conventions
//  - Nodes: the linear mesh's vertices first, with the same indices, then one node per edge in
//    `edges` order: node num_corners() + i sits on edge i. So the corner part of a state is its
//    head, x.head(dim * num_corners()), a state of the linear mesh.
//  - Local node order (VTK's quadratic triangle and tetra): the corners 0..dim, then the edges
//      triangle: 3 (0,1), 4 (1,2), 5 (2,0)
//      tetrahedron: 4 (0,1), 5 (1,2), 6 (2,0), 7 (0,3), 8 (1,3), 9 (2,3).
//  - States interleave like a linear mesh's: component i of node v is x[dim * v + i].
//  - Quadratic facets (boundary triangles of tets, boundary edges of triangles): the linear
//    facet's corners in its order (outward normal, as boundary_facets), then its edge nodes:
//    2D (a, b, ab), 3D (a, b, c, ab, bc, ca) - the 1D and 2D P2 orders of the same rule.
#include <Eigen/Core>
#include <array>
#include <functional>
#include <vector>

#include "forward/mesh/mesh.hpp"

namespace tailor {

// Moving nodes (e.g. mapping the whole mesh): move the corners in both rest_positions and
// corners.rest_positions, which facet selections (boundary_facets_where on corners) read.
struct QuadraticMesh {
  Mesh corners;                    // the linear mesh: corner positions, elements and regions
  Eigen::MatrixXd rest_positions;  // num_nodes x dim: the corners, then the edge nodes
  Eigen::MatrixXi elements;        // num_elements x 6 (triangles) or 10 (tets), local order above
  Eigen::MatrixXi edges;           // num_edges x 2 corner vertices, lower first, sorted

  int dim() const { return static_cast<int>(rest_positions.cols()); }
  int num_nodes() const { return static_cast<int>(rest_positions.rows()); }
  int num_corners() const { return corners.num_vertices(); }
  int num_elements() const { return static_cast<int>(elements.rows()); }
  const Eigen::VectorXi& element_regions() const { return corners.element_regions; }
};

// Local edges (pairs of local corners) of a simplex of dimension SimplexDim (1: a segment, 2: a
// triangle, 3: a tetrahedron) in the local order of their nodes: edge i is node SimplexDim+1+i.
template <int SimplexDim>
const std::array<std::array<int, 2>, SimplexDim*(SimplexDim + 1) / 2>& simplex_edges();
template <>
const std::array<std::array<int, 2>, 1>& simplex_edges<1>();
template <>
const std::array<std::array<int, 2>, 3>& simplex_edges<2>();
template <>
const std::array<std::array<int, 2>, 6>& simplex_edges<3>();

// The quadratic mesh of a linear one (validated: throws MeshError as validate_mesh). Edges shared
// by several elements get one node; element regions are carried over.
QuadraticMesh make_quadratic_mesh(const Mesh& linear);

// The edge node between corner vertices a and b; -1 when they share no edge.
int edge_node(const QuadraticMesh& mesh, int a, int b);

// Linear facets (rows of dim corner vertices, as from boundary_facets or boundary_facets_where
// on mesh.corners) with their edge nodes appended, in the order of the header. Throws
// std::invalid_argument when a facet's edge is not an edge of the mesh.
Eigen::MatrixXi quadratic_facets(const QuadraticMesh& mesh, const Eigen::MatrixXi& facets);

// The nodes (corner and edge nodes alike) whose rest position satisfies `on`, ascending: for
// Dirichlet conditions, which then hold the edge nodes of a clamped face too.
std::vector<int> nodes_where(const QuadraticMesh& mesh, const std::function<bool(const Eigen::VectorXd&)>& on);
// The DOFs of `nodes` (every component), for Elimination::dirichlet.
std::vector<int> node_dofs(const QuadraticMesh& mesh, const std::vector<int>& nodes);

// A field on the linear mesh's vertices (interleaved, dim values per vertex; e.g. a state)
// extended to every node: an edge node gets the mean of its edge's ends, the value of the
// linear interpolant at the midpoint (so for moved edge nodes it is not the field there).
Eigen::VectorXd extend_corner_field(const QuadraticMesh& mesh, const Eigen::VectorXd& corner_field);

// Rest positions of every node as a flat state (interleaved).
Eigen::VectorXd quadratic_rest_state(const QuadraticMesh& mesh);

}  // namespace tailor
