// Structured generators: counts, numbering, positive volumes, conforming faces, outward
// boundary normals.
#include "forward/mesh/generate.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace tailor::generate_test {
namespace {

TEST(BoxTetMesh, CountsNumberingAndPositiveVolumes) {
  const Eigen::Vector3d lo(-1.0, 0.0, 2.0), hi(1.0, 1.5, 3.0);
  const int nx = 2, ny = 3, nz = 4;
  const Mesh mesh = box_tet_mesh(lo, hi, nx, ny, nz);
  ASSERT_EQ(mesh.dim(), 3);
  ASSERT_EQ(mesh.num_vertices(), 3 * 4 * 5);
  ASSERT_EQ(mesh.num_elements(), 6 * nx * ny * nz);
  ASSERT_EQ(mesh.element_regions.size(), mesh.num_elements());
  EXPECT_TRUE((mesh.element_regions.array() == 0).all());

  for (int k = 0; k <= nz; ++k) {
    for (int j = 0; j <= ny; ++j) {
      for (int i = 0; i <= nx; ++i) {
        const int v = i + (nx + 1) * (j + (ny + 1) * k);
        const Eigen::Vector3d expected =
            lo + (hi - lo).cwiseProduct(Eigen::Vector3d(double(i) / nx, double(j) / ny, double(k) / nz));
        EXPECT_TRUE(mesh.rest_positions.row(v).transpose().isApprox(expected, 1e-14)) << "vertex " << v;
      }
    }
  }
  EXPECT_DOUBLE_EQ(mesh.rest_positions.col(0).maxCoeff(), hi.x());
  EXPECT_DOUBLE_EQ(mesh.rest_positions.col(2).minCoeff(), lo.z());

  const Eigen::VectorXd volumes = element_volumes(mesh);
  const double cell_volume = (hi - lo).prod() / (nx * ny * nz);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    EXPECT_NEAR(volumes[e], cell_volume / 6.0, 1e-14) << "element " << e;  // Kuhn tets are equal
  }
  EXPECT_NEAR(volumes.sum(), (hi - lo).prod(), 1e-12);
  EXPECT_NO_THROW(validate_mesh(mesh, "box"));
}

TEST(BoxTetMesh, FacesConformAndBoundaryIsTheBoxSurface) {
  const Eigen::Vector3d lo(0.0, 0.0, 0.0), hi(3.0, 2.0, 0.5);
  const int nx = 3, ny = 4, nz = 2;
  const Mesh mesh = box_tet_mesh(lo, hi, nx, ny, nz);
  Eigen::VectorXi owner;
  const Eigen::MatrixXi facets = boundary_facets(mesh, &owner);
  // A non-conforming split would leave unmatched interior faces and more boundary facets.
  ASSERT_EQ(facets.rows(), 2 * 2 * (nx * ny + ny * nz + nz * nx));
  const Eigen::Vector3d size = hi - lo;
  const Eigen::Vector3d center = (lo + hi) / 2;
  double area = 0.0;
  for (int f = 0; f < facets.rows(); ++f) {
    const Eigen::Vector3d p = mesh.rest_positions.row(facets(f, 0));
    const Eigen::Vector3d q = mesh.rest_positions.row(facets(f, 1));
    const Eigen::Vector3d r = mesh.rest_positions.row(facets(f, 2));
    const Eigen::Vector3d normal = (q - p).cross(r - p);
    area += normal.norm() / 2;
    // The normal is axis-aligned and points out of the face of the box the facet lies on.
    int axis = 0;
    normal.cwiseAbs().maxCoeff(&axis);
    EXPECT_NEAR(normal.norm(), std::abs(normal[axis]), 1e-12) << "facet " << f;
    const double side = normal[axis] > 0 ? hi[axis] : lo[axis];
    for (const auto* x : {&p, &q, &r}) EXPECT_DOUBLE_EQ((*x)[axis], side) << "facet " << f;
    EXPECT_GT(normal.dot((p + q + r) / 3 - center), 0.0) << "facet " << f;
  }
  EXPECT_NEAR(area, 2 * (size.x() * size.y() + size.y() * size.z() + size.z() * size.x()), 1e-12);

  // Every interior face joins exactly two tetrahedra: 4 faces per tet = boundary + 2 * pairs.
  const Eigen::MatrixXi pairs = element_adjacency(mesh);
  EXPECT_EQ(4 * mesh.num_elements(), facets.rows() + 2 * pairs.rows());
  for (int i = 0; i < pairs.rows(); ++i) {
    EXPECT_LT(pairs(i, 0), pairs(i, 1));
    if (i > 0) {
      EXPECT_TRUE(pairs(i - 1, 0) < pairs(i, 0) ||
                  (pairs(i - 1, 0) == pairs(i, 0) && pairs(i - 1, 1) < pairs(i, 1)));
    }
  }
  // Within one cube the 6 Kuhn tets form a ring around the diagonal: 6 shared faces.
  const Mesh cube = box_tet_mesh(lo, hi, 1, 1, 1);
  EXPECT_EQ(element_adjacency(cube).rows(), 6);
  EXPECT_EQ(boundary_facets(cube).rows(), 12);
}

TEST(RectangleTriangleMesh, CountsAreasAndBoundary) {
  const Eigen::Vector2d lo(-1.0, 2.0), hi(2.0, 4.0);
  const int nx = 3, ny = 5;
  const Mesh mesh = rectangle_triangle_mesh(lo, hi, nx, ny);
  ASSERT_EQ(mesh.dim(), 2);
  ASSERT_EQ(mesh.num_vertices(), 4 * 6);
  ASSERT_EQ(mesh.num_elements(), 2 * nx * ny);
  const int corner = nx + (nx + 1) * ny;  // vertex (nx, ny)
  EXPECT_TRUE(mesh.rest_positions.row(corner).transpose().isApprox(hi));
  EXPECT_TRUE(mesh.rest_positions.row(1).transpose().isApprox(Eigen::Vector2d(0.0, 2.0)));

  const Eigen::VectorXd areas = element_volumes(mesh);
  EXPECT_GT(areas.minCoeff(), 0.0);
  EXPECT_NEAR(areas.sum(), 6.0, 1e-12);
  EXPECT_NO_THROW(validate_mesh(mesh, "rectangle"));

  const Eigen::MatrixXi edges = boundary_facets(mesh);
  ASSERT_EQ(edges.rows(), 2 * (nx + ny));
  double perimeter = 0.0;
  const Eigen::Vector2d center = (lo + hi) / 2;
  for (int f = 0; f < edges.rows(); ++f) {
    const Eigen::Vector2d p = mesh.rest_positions.row(edges(f, 0)), q = mesh.rest_positions.row(edges(f, 1));
    perimeter += (q - p).norm();
    const Eigen::Vector2d outward((q - p).y(), -(q - p).x());
    EXPECT_GT(outward.dot((p + q) / 2 - center), 0.0) << "edge " << f;
  }
  EXPECT_NEAR(perimeter, 2 * (3.0 + 2.0), 1e-12);
  EXPECT_EQ(3 * mesh.num_elements(), edges.rows() + 2 * element_adjacency(mesh).rows());
}

TEST(Generators, RejectInvalidArguments) {
  const Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Ones();
  EXPECT_THROW(box_tet_mesh(lo, hi, 0, 1, 1), std::invalid_argument);
  EXPECT_THROW(box_tet_mesh(lo, hi, 1, -2, 1), std::invalid_argument);
  EXPECT_THROW(box_tet_mesh(hi, lo, 1, 1, 1), std::invalid_argument);
  EXPECT_THROW(box_tet_mesh(lo, Eigen::Vector3d(1, 0, 1), 1, 1, 1), std::invalid_argument);
  EXPECT_THROW(box_tet_mesh(lo, Eigen::Vector3d(1, std::numeric_limits<double>::quiet_NaN(), 1), 1, 1, 1),
               std::invalid_argument);
  EXPECT_THROW(box_tet_mesh(lo, hi, 100000, 100000, 100000), std::invalid_argument);  // int overflow
  const Eigen::Vector2d lo2 = Eigen::Vector2d::Zero(), hi2 = Eigen::Vector2d::Ones();
  EXPECT_THROW(rectangle_triangle_mesh(lo2, hi2, 0, 1), std::invalid_argument);
  EXPECT_THROW(rectangle_triangle_mesh(lo2, hi2, 1, -1), std::invalid_argument);
  EXPECT_THROW(rectangle_triangle_mesh(lo2, Eigen::Vector2d(1, 0), 1, 1), std::invalid_argument);
  EXPECT_THROW(rectangle_triangle_mesh(hi2, lo2, 1, 1), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::generate_test
