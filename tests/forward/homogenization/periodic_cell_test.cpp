#include "forward/homogenization/periodic_cell.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "forward/homogenization/cell_mesh.hpp"

namespace tailor::periodic_cell_test {
namespace {

Eigen::Matrix2d skewed_lattice() {
  Eigen::Matrix2d A;
  A << 2.0, 0.7, 0.0, 1.3;  // a1 = (2, 0), a2 = (0.7, 1.3)
  return A;
}

TEST(PeriodicCell, PairsEveryBoundaryVertexOfASkewedTriangleCell) {
  const Eigen::Vector2d origin(-0.4, 0.25);
  for (const TriangleSplit split :
       {TriangleSplit::forward, TriangleSplit::backward, TriangleSplit::crossed}) {
    const Mesh mesh = lattice_triangle_mesh(skewed_lattice(), origin, 5, 4, split);
    const PeriodicCell cell = make_periodic_cell(mesh, skewed_lattice(), origin);
    const int centres = split == TriangleSplit::crossed ? 20 : 0;
    EXPECT_EQ(cell.num_periodic_nodes(), 5 * 4 + centres);
    // Corners are one node; a vertex on the a1 face pairs with its translate by a1.
    EXPECT_EQ(cell.master[5], 0);
    EXPECT_EQ(cell.master[5 + 6 * 4], 0);
    EXPECT_EQ(cell.master[6 * 4 + 2], 2);
    EXPECT_NEAR(cell.volume(), 2.6, 1e-14);
  }
}

TEST(PeriodicCell, PairsATetCellAndBuildsTheElimination) {
  Eigen::Matrix3d A;
  A << 1.0, 0.3, -0.2, 0.0, 1.1, 0.4, 0.0, 0.0, 0.9;
  const Mesh mesh = lattice_tet_mesh(A, Eigen::Vector3d::Zero(), 3, 2, 4);
  const PeriodicCell cell = make_periodic_cell(mesh, A, Eigen::Vector3d::Zero());
  EXPECT_EQ(cell.num_periodic_nodes(), 3 * 2 * 4);
  const Elimination elimination = periodic_elimination(cell, Eigen::Matrix3d::Zero());
  // One node (the anchor) is fixed: the rigid translation is removed.
  EXPECT_EQ(elimination.num_free(), 3 * (3 * 2 * 4 - 1));
  EXPECT_TRUE(elimination.is_selection());
  // A periodic fluctuation: copies of a node move together.
  const Vector y = Vector::LinSpaced(elimination.num_free(), 0.0, 1.0);
  const Vector x = elimination.expand(y) - macro_offset(cell, Eigen::Matrix3d::Zero());
  for (int v = 0; v < mesh.num_vertices(); ++v)
    EXPECT_LT((x.segment<3>(3 * v) - x.segment<3>(3 * cell.master[v])).norm(), 1e-14);
  // The affine part is the macro displacement gradient applied to the rest positions.
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  H(0, 1) = 0.1;
  const Vector x0 = macro_offset(cell, H);
  EXPECT_NEAR(x0[3 * 7] - mesh.rest_positions(7, 0), 0.1 * mesh.rest_positions(7, 1), 1e-15);
}

TEST(PeriodicCell, BoxCellFromTheBoundingBox) {
  const Mesh mesh =
      lattice_triangle_mesh(Eigen::Vector2d(3.0, 2.0).asDiagonal(), Eigen::Vector2d(1.0, -1.0), 6, 4);
  const PeriodicCell cell = make_box_periodic_cell(mesh);
  EXPECT_NEAR(cell.volume(), 6.0, 1e-14);
  EXPECT_EQ(cell.num_periodic_nodes(), 24);
}

TEST(PeriodicCell, RejectsANonPeriodicMeshNamingTheUnmatchedVertex) {
  Mesh mesh = lattice_triangle_mesh(skewed_lattice(), Eigen::Vector2d::Zero(), 5, 4);
  // Move vertex (5, 2) (on the a1 face) along the face: its partner (0, 2) no longer matches.
  const int moved = 5 + 6 * 2;
  mesh.rest_positions.row(moved) += 1e-3 * skewed_lattice().col(1).transpose();
  try {
    make_periodic_cell(mesh, skewed_lattice(), Eigen::Vector2d::Zero());
    FAIL() << "a non-periodic mesh was accepted";
  } catch (const PeriodicityError& e) {
    EXPECT_THAT(e.what(), testing::HasSubstr("vertex " + std::to_string(moved) + " at"));
    EXPECT_THAT(e.what(), testing::HasSubstr("vertex 12 at"));  // its former partner (0, 2)
    EXPECT_THAT(e.what(), testing::HasSubstr("unmatched"));
  }
}

TEST(PeriodicCell, RejectsWrongLatticesAndOutsideVertices) {
  const Mesh mesh = lattice_triangle_mesh(Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero(), 4, 4);
  // The cell is twice as large as the mesh: vertices do not tile it.
  EXPECT_THROW(make_periodic_cell(mesh, 2.0 * Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero()),
               PeriodicityError);
  // Vertices outside a smaller cell.
  EXPECT_THROW(make_periodic_cell(mesh, 0.5 * Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero()),
               PeriodicityError);
  Eigen::Matrix2d left_handed;
  left_handed << 0.0, 1.0, 1.0, 0.0;
  EXPECT_THROW(make_periodic_cell(mesh, left_handed, Eigen::Vector2d::Zero()), std::invalid_argument);
  EXPECT_THROW(make_periodic_cell(mesh, Eigen::Matrix3d::Identity(), Eigen::Vector2d::Zero()),
               std::invalid_argument);
}

}  // namespace
}  // namespace tailor::periodic_cell_test
