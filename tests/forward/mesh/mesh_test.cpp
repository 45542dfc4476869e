// validate_mesh, element_volumes, boundary_facets and element_adjacency on hand-made meshes.
#include "forward/mesh/mesh.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "mesh_test_support.hpp"

namespace tailor::mesh_test {
namespace {

using test::expect_mesh_error;

// Two unit-corner tetrahedra sharing the face (1, 2, 3).
Mesh two_tets() {
  Mesh mesh;
  mesh.rest_positions.resize(5, 3);
  mesh.rest_positions << 0, 0, 0,  //
      1, 0, 0,                     //
      0, 1, 0,                     //
      0, 0, 1,                     //
      1, 1, 1;
  mesh.elements.resize(2, 4);
  mesh.elements << 0, 1, 2, 3,  //
      4, 1, 3, 2;
  mesh.element_regions = Eigen::VectorXi::Zero(2);
  return mesh;
}

// The unit square as two counter-clockwise triangles.
Mesh two_triangles() {
  Mesh mesh;
  mesh.rest_positions.resize(4, 2);
  mesh.rest_positions << 0, 0, 1, 0, 1, 1, 0, 1;
  mesh.elements.resize(2, 3);
  mesh.elements << 0, 1, 2, 0, 2, 3;
  mesh.element_regions = Eigen::VectorXi::Zero(2);
  return mesh;
}

TEST(ElementVolumes, TetrahedraAndTriangles) {
  const Eigen::VectorXd tets = element_volumes(two_tets());
  ASSERT_EQ(tets.size(), 2);
  EXPECT_NEAR(tets[0], 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(tets[1], 1.0 / 3.0, 1e-15);
  const Eigen::VectorXd triangles = element_volumes(two_triangles());
  EXPECT_NEAR(triangles[0], 0.5, 1e-15);
  EXPECT_NEAR(triangles[1], 0.5, 1e-15);
}

TEST(ValidateMesh, AcceptsValidMeshesAtAnyScale) {
  EXPECT_NO_THROW(validate_mesh(two_tets(), "two tets"));
  EXPECT_NO_THROW(validate_mesh(two_triangles(), "two triangles"));
  // The degeneracy tolerance is relative to the element size, so tiny meshes stay valid.
  Mesh tiny = two_tets();
  tiny.rest_positions *= 1e-6;
  EXPECT_NO_THROW(validate_mesh(tiny, "tiny"));
}

TEST(ValidateMesh, RejectsBadShapes) {
  Mesh mesh = two_tets();
  mesh.elements.conservativeResize(2, 3);
  expect_mesh_error([&] { validate_mesh(mesh, "shape source"); }, {"shape source", "3 vertices", "needs 4"});

  mesh = two_tets();
  mesh.rest_positions.conservativeResize(5, 1);
  expect_mesh_error([&] { validate_mesh(mesh, "src"); }, {"src", "1 columns"});

  mesh = two_tets();
  mesh.element_regions.resize(1);
  expect_mesh_error([&] { validate_mesh(mesh, "src"); }, {"src", "1 element regions for 2 elements"});

  mesh = two_tets();
  mesh.elements.resize(0, 4);
  mesh.element_regions.resize(0);
  expect_mesh_error([&] { validate_mesh(mesh, "src"); }, {"src", "no elements"});
}

TEST(ValidateMesh, RejectsIndexOutOfRangeAndNonFiniteCoordinates) {
  Mesh mesh = two_tets();
  mesh.elements(1, 2) = 7;
  expect_mesh_error([&] { validate_mesh(mesh, "src"); },
                    {"src", "element 1 references vertex 7", "only 5 vertices"});
  mesh.elements(1, 2) = -1;
  expect_mesh_error([&] { validate_mesh(mesh, "src"); }, {"element 1 references vertex -1"});

  mesh = two_tets();
  mesh.rest_positions(3, 1) = std::numeric_limits<double>::quiet_NaN();
  expect_mesh_error([&] { validate_mesh(mesh, "src"); }, {"src", "vertex 3", "non-finite"});
  mesh.rest_positions(3, 1) = std::numeric_limits<double>::infinity();
  expect_mesh_error([&] { validate_mesh(mesh, "src"); }, {"vertex 3", "inf"});
}

// A vertex that no element uses (a geometry point saved with the mesh) is refused, naming it:
// it has no stiffness and no mass, so solves, eigensolves and periodic solves fail elsewhere.
TEST(ValidateMesh, RejectsVerticesUsedByNoElementNamingThem) {
  Mesh mesh = two_tets();
  mesh.rest_positions.conservativeResize(7, 3);
  mesh.rest_positions.row(5) << 3, 3, 3;
  mesh.rest_positions.row(6) << 4, 4, 4;
  expect_mesh_error([&] { validate_mesh(mesh, "src"); },
                    {"src", "2 of 7 vertices are used by no element", "0-based: 5, 6", "Remove them"});
  Mesh flat = two_triangles();
  flat.elements.conservativeResize(1, 3);
  flat.element_regions.conservativeResize(1);
  expect_mesh_error([&] { validate_mesh(flat, "flat"); }, {"flat", "1 of 4 vertices", "0-based: 3"});
}

TEST(ValidateMesh, RejectsInvertedAndDegenerateElementsNamingThem) {
  Mesh mesh = two_tets();
  mesh.elements.row(1) << 4, 1, 2, 3;  // swapped: negative orientation
  expect_mesh_error([&] { validate_mesh(mesh, "src"); },
                    {"src", "element 1 is inverted", "-0.333333", "vertices 4 1 2 3"});

  mesh = two_tets();
  mesh.rest_positions.row(3) << 0.5, 0.5, 0;  // flattens element 0 into the plane z = 0
  expect_mesh_error([&] { validate_mesh(mesh, "src"); }, {"element 0 is degenerate", "volume 0"});

  Mesh flat = two_triangles();
  flat.elements.row(0) << 0, 2, 1;
  expect_mesh_error([&] { validate_mesh(flat, "flat"); }, {"flat", "element 0 is inverted", "area -0.5"});
  flat = two_triangles();
  flat.elements.row(1) << 0, 2, 2;
  expect_mesh_error([&] { validate_mesh(flat, "flat"); }, {"element 1 is degenerate"});
}

// Outward normal of a boundary facet: a triangle's (q - p) x (r - p), an edge's (q - p)
// turned clockwise.
Eigen::VectorXd facet_normal(const Mesh& mesh, const Eigen::MatrixXi& facets, int f) {
  const auto& x = mesh.rest_positions;
  if (mesh.dim() == 3) {
    const Eigen::Vector3d p = x.row(facets(f, 0)), q = x.row(facets(f, 1)), r = x.row(facets(f, 2));
    return (q - p).cross(r - p);
  }
  const Eigen::Vector2d d = x.row(facets(f, 1)) - x.row(facets(f, 0));
  return Eigen::Vector2d(d.y(), -d.x());
}

// Checks that every boundary facet's normal points away from its owner's centroid.
void expect_outward(const Mesh& mesh) {
  Eigen::VectorXi owner;
  const Eigen::MatrixXi facets = boundary_facets(mesh, &owner);
  ASSERT_EQ(owner.size(), facets.rows());
  for (int f = 0; f < facets.rows(); ++f) {
    Eigen::VectorXd centroid = Eigen::VectorXd::Zero(mesh.dim());
    for (int k = 0; k <= mesh.dim(); ++k)
      centroid += mesh.rest_positions.row(mesh.elements(owner[f], k)).transpose();
    centroid /= mesh.dim() + 1;
    const Eigen::VectorXd away = mesh.rest_positions.row(facets(f, 0)).transpose() - centroid;
    EXPECT_GT(facet_normal(mesh, facets, f).dot(away), 0.0) << "facet " << f;
    // Every vertex of the facet belongs to the owner.
    for (int k = 0; k < facets.cols(); ++k) {
      EXPECT_TRUE((mesh.elements.row(owner[f]).array() == facets(f, k)).any());
    }
  }
}

TEST(BoundaryFacets, TwoTetsHaveSixOutwardFaces) {
  const Mesh mesh = two_tets();
  Eigen::VectorXi owner;
  const Eigen::MatrixXi facets = boundary_facets(mesh, &owner);
  ASSERT_EQ(facets.rows(), 6);
  ASSERT_EQ(facets.cols(), 3);
  EXPECT_EQ((owner.array() == 0).count(), 3);
  EXPECT_EQ((owner.array() == 1).count(), 3);
  // The shared face (1, 2, 3) is not on the boundary.
  for (int f = 0; f < 6; ++f) {
    const bool shared = (facets.row(f).array() != 0).all() && (facets.row(f).array() != 4).all();
    EXPECT_FALSE(shared) << "facet " << f;
  }
  expect_outward(mesh);
  EXPECT_EQ(boundary_facets(mesh).rows(), 6);  // the owner output is optional
}

TEST(BoundaryFacets, TwoTrianglesHaveFourOutwardEdges) {
  const Mesh mesh = two_triangles();
  const Eigen::MatrixXi edges = boundary_facets(mesh);
  ASSERT_EQ(edges.rows(), 4);
  ASSERT_EQ(edges.cols(), 2);
  expect_outward(mesh);
}

TEST(ElementAdjacency, PairsThroughSharedFacetsOnly) {
  Eigen::MatrixXi pairs = element_adjacency(two_tets());
  ASSERT_EQ(pairs.rows(), 1);
  ASSERT_EQ(pairs.cols(), 2);
  EXPECT_EQ(pairs(0, 0), 0);
  EXPECT_EQ(pairs(0, 1), 1);

  pairs = element_adjacency(two_triangles());
  ASSERT_EQ(pairs.rows(), 1);
  EXPECT_EQ(pairs(0, 0), 0);
  EXPECT_EQ(pairs(0, 1), 1);

  // Tetrahedra touching only at the edge (0, 3) are not adjacent.
  Mesh mesh = two_tets();
  mesh.rest_positions.conservativeResize(6, 3);
  mesh.rest_positions.row(4) << -1, 0, 0;
  mesh.rest_positions.row(5) << -1, -1, 0;
  mesh.elements.row(1) << 0, 4, 5, 3;
  ASSERT_NO_THROW(validate_mesh(mesh, "edge-sharing tets"));
  EXPECT_EQ(element_adjacency(mesh).rows(), 0);
  EXPECT_EQ(boundary_facets(mesh).rows(), 8);
}

}  // namespace
}  // namespace tailor::mesh_test
