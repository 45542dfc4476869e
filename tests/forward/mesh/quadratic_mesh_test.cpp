// Quadratic meshes from linear ones: node counts (Euler: one node per edge), shared edge nodes
// at the midpoints, the local node order, regions carried over, quadratic facets, node
// selection and the extension of corner fields.
#include "forward/mesh/quadratic_mesh.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>
#include <stdexcept>

#include "forward/mesh/generate.hpp"

namespace tailor::quadratic_mesh_test {
namespace {

// Every element's edge node sits at the midpoint of the element's corresponding local edge.
template <int Dim>
void expect_local_order(const QuadraticMesh& q) {
  const auto& edges = simplex_edges<Dim>();
  for (int e = 0; e < q.num_elements(); ++e)
    for (std::size_t i = 0; i < edges.size(); ++i) {
      const int a = q.elements(e, edges[i][0]), b = q.elements(e, edges[i][1]);
      const int m = q.elements(e, Dim + 1 + static_cast<int>(i));
      EXPECT_EQ(m, edge_node(q, a, b));
      EXPECT_LT((q.rest_positions.row(m) - 0.5 * (q.rest_positions.row(a) + q.rest_positions.row(b))).norm(), 1e-15);
    }
}

TEST(QuadraticMesh, TrianglesShareEdgeNodes) {
  Mesh linear = rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(2, 1), 3, 2);
  for (int e = 0; e < linear.num_elements(); ++e) linear.element_regions[e] = e % 3;
  const QuadraticMesh q = make_quadratic_mesh(linear);
  // Edges of an nx x ny grid of squares split in two: horizontal, vertical and one diagonal each.
  const int edges = 3 * 3 + 4 * 2 + 3 * 2;
  EXPECT_EQ(q.edges.rows(), edges);
  EXPECT_EQ(q.num_corners(), 12);
  EXPECT_EQ(q.num_nodes(), 12 + edges);
  EXPECT_EQ(q.elements.cols(), 6);
  EXPECT_EQ(q.element_regions(), linear.element_regions);
  EXPECT_EQ(q.rest_positions.topRows(12), linear.rest_positions);
  std::set<int> used;
  for (int e = 0; e < q.num_elements(); ++e)
    for (int a = 0; a < 6; ++a) used.insert(q.elements(e, a));
  EXPECT_EQ(static_cast<int>(used.size()), q.num_nodes());  // every node in some element
  expect_local_order<2>(q);
  EXPECT_EQ(edge_node(q, 0, 11), -1);
}

TEST(QuadraticMesh, TetsShareEdgeNodes) {
  const Mesh linear = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1), 2, 2, 2);
  const QuadraticMesh q = make_quadratic_mesh(linear);
  // Euler for a ball: V - E + F - T = 1.
  std::set<std::array<int, 3>> faces;
  for (int e = 0; e < linear.num_elements(); ++e)
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> f{};
      int n = 0;
      for (int a = 0; a < 4; ++a)
        if (a != skip) f[static_cast<std::size_t>(n++)] = linear.elements(e, a);
      std::sort(f.begin(), f.end());
      faces.insert(f);
    }
  EXPECT_EQ(linear.num_vertices() - q.edges.rows() + static_cast<int>(faces.size()) - linear.num_elements(), 1);
  EXPECT_EQ(q.elements.cols(), 10);
  expect_local_order<3>(q);
}

TEST(QuadraticMesh, FacetsNodesAndFields) {
  const Mesh linear = rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), 2, 2);
  const QuadraticMesh q = make_quadratic_mesh(linear);
  const Eigen::MatrixXi right =
      boundary_facets_where(linear, [](const Eigen::VectorXd& X) { return X[0] > 1 - 1e-12; });
  const Eigen::MatrixXi facets = quadratic_facets(q, right);
  ASSERT_EQ(facets.rows(), 2);
  ASSERT_EQ(facets.cols(), 3);
  for (int k = 0; k < 2; ++k) EXPECT_EQ(facets(k, 2), edge_node(q, facets(k, 0), facets(k, 1)));
  // Clamping x = 1 takes 3 corners and the 2 edge nodes between them.
  const std::vector<int> nodes = nodes_where(q, [](const Eigen::VectorXd& X) { return X[0] > 1 - 1e-12; });
  EXPECT_EQ(nodes.size(), 5u);
  EXPECT_EQ(node_dofs(q, nodes).size(), 10u);
  // A linear field extends to the linear field at the nodes.
  Eigen::VectorXd corner(2 * q.num_corners());
  for (int v = 0; v < q.num_corners(); ++v)
    corner.segment<2>(2 * v) = Eigen::Vector2d(1 + 2 * linear.rest_positions(v, 0), 3 * linear.rest_positions(v, 1));
  const Eigen::VectorXd all = extend_corner_field(q, corner);
  const Eigen::VectorXd rest = quadratic_rest_state(q);
  for (int v = 0; v < q.num_nodes(); ++v) {
    EXPECT_NEAR(all[2 * v], 1 + 2 * rest[2 * v], 1e-14);
    EXPECT_NEAR(all[2 * v + 1], 3 * rest[2 * v + 1], 1e-14);
  }
  Eigen::MatrixXi bad(1, 2);
  bad << 0, 8;  // opposite corners: no edge
  EXPECT_THROW(quadratic_facets(q, bad), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::quadratic_mesh_test
