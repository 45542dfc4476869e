// The consistent P2 mass matrix: the classical 6-node triangle matrix, total mass under a rigid
// translation, and exact kinetic energy of quadratic velocity fields on straight-sided meshes.
#include "forward/fem/quadratic_mass.hpp"

#include <gtest/gtest.h>

#include "forward/mesh/generate.hpp"

namespace tailor::quadratic_mass_test {
namespace {

TEST(QuadraticMass, SixNodeTriangleMatchesTheClassicalMatrix) {
  Mesh one;
  one.rest_positions.resize(3, 2);
  one.rest_positions << 0, 0, 2, 0, 0, 1;  // area 1
  one.elements.resize(1, 3);
  one.elements << 0, 1, 2;
  one.element_regions = Eigen::VectorXi::Zero(1);
  const QuadraticMesh q = make_quadratic_mesh(one);
  const Matrix M = Matrix(quadratic_mass_matrix(q, Eigen::VectorXd::Constant(1, 3.0)));
  const int e = q.elements(0, 3);  // an edge node
  EXPECT_NEAR(M(0, 0), 3.0 / 30.0, 1e-14);
  EXPECT_NEAR(M(0, 2), -3.0 / 180.0, 1e-14);
  EXPECT_NEAR(M(2 * e, 2 * e), 3.0 * 8.0 / 45.0, 1e-14);
  EXPECT_NEAR(M(0, 1), 0.0, 0.0);  // components do not couple
}

TEST(QuadraticMass, RigidTranslationAndQuadraticFields) {
  for (int dim : {2, 3}) {
    const QuadraticMesh q =
        dim == 3 ? make_quadratic_mesh(box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1), 2, 1, 1))
                 : make_quadratic_mesh(rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(2, 1), 3, 2));
    const double rho = 1.5;
    const SparseMatrix M = quadratic_mass_matrix(q, Eigen::VectorXd::Constant(q.num_elements(), rho));
    Vector u = Vector::Zero(dim * q.num_nodes());
    for (int v = 0; v < q.num_nodes(); ++v) u[dim * v + dim - 1] = 1.0;
    EXPECT_NEAR(u.dot(M * u), rho * 2.0, 1e-12) << dim << "D";  // total mass
    // u = x y along the first axis: int rho x^2 y^2 over [0,2]x[0,1](x[0,1]) = rho * 8/3 * 1/3.
    Vector w = Vector::Zero(dim * q.num_nodes());
    for (int v = 0; v < q.num_nodes(); ++v) w[dim * v] = q.rest_positions(v, 0) * q.rest_positions(v, 1);
    EXPECT_NEAR(w.dot(M * w), rho * 8.0 / 9.0, 1e-12) << dim << "D";
  }
}

}  // namespace
}  // namespace tailor::quadratic_mass_test
