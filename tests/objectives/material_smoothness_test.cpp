#include "objectives/material_smoothness.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "../support/fem_fixtures.hpp"
#include "forward/core/symmetric_eigen.hpp"
#include "objective_checks.hpp"

namespace tailor::material_smoothness_test {
namespace {

using testing::random_vector;

Vector sorted_eigenvalues(const SparseMatrix& L) {
  return symmetric_eigenvalues(Matrix(L));  // ascending
}

std::string weighting_name(AdjacencyWeighting w) {
  return w == AdjacencyWeighting::unit ? "unit" : "facet_over_distance";
}

class LaplacianTest : public ::testing::TestWithParam<std::tuple<int, AdjacencyWeighting>> {};

TEST_P(LaplacianTest, SymmetricZeroRowSumsPsdConstantNullSpace) {
  const auto [dim, weighting] = GetParam();
  const Mesh mesh = testing::small_mesh(dim);
  const SparseMatrix L = MaterialSmoothness::laplacian(mesh, weighting);
  const int m = mesh.num_elements();
  ASSERT_EQ(L.rows(), m);
  ASSERT_EQ(L.cols(), m);
  const Matrix dense(L);
  EXPECT_EQ((dense - dense.transpose()).norm(), 0.0);
  EXPECT_LE((dense * Vector::Ones(m)).norm(), 1e-12 * dense.norm());
  // Off-diagonal entries are -w_ef < 0 exactly on the adjacent pairs.
  const Eigen::MatrixXi pairs = element_adjacency(mesh);
  EXPECT_EQ(L.nonZeros(), m + 2 * pairs.rows());
  for (Eigen::Index k = 0; k < pairs.rows(); ++k) EXPECT_LT(dense(pairs(k, 0), pairs(k, 1)), 0.0);
  // PSD with a one-dimensional null space (the mesh is connected): the constants.
  const Vector lambda = sorted_eigenvalues(L);
  const double tol = 1e-12 * lambda.maxCoeff();
  EXPECT_GE(lambda[0], -tol);
  EXPECT_LE(std::abs(lambda[0]), tol);
  EXPECT_GT(lambda[1], 1e-6 * lambda.maxCoeff());
  // The quadratic form is the weighted sum of squared jumps.
  const Vector w = MaterialSmoothness::adjacency_weights(mesh, pairs, weighting);
  const Vector q = random_vector(m, 3);
  double jumps = 0;
  for (Eigen::Index k = 0; k < pairs.rows(); ++k)
    jumps += w[k] * std::pow(q[pairs(k, 0)] - q[pairs(k, 1)], 2);
  EXPECT_NEAR(q.dot(L * q), jumps, 1e-12 * jumps);
}

INSTANTIATE_TEST_SUITE_P(DimsAndWeightings, LaplacianTest,
                         ::testing::Combine(::testing::Values(2, 3),
                                            ::testing::Values(AdjacencyWeighting::unit,
                                                              AdjacencyWeighting::facet_over_distance)),
                         [](const auto& param_info) {
                           return "dim" + std::to_string(std::get<0>(param_info.param)) + "_" +
                                  weighting_name(std::get<1>(param_info.param));
                         });

TEST(Laplacian, TwoTrianglesOfASquare) {
  // Unit square, two triangles sharing the diagonal (length sqrt 2); centroids (2/3, 1/3) and
  // (1/3, 2/3) are sqrt(2)/3 apart, so the facet-over-distance weight is 3.
  const Mesh mesh = rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), 1, 1);
  Matrix expected(2, 2);
  expected << 1, -1, -1, 1;
  EXPECT_EQ(Matrix(MaterialSmoothness::laplacian(mesh)), expected);
  EXPECT_LE(
      (Matrix(MaterialSmoothness::laplacian(mesh, AdjacencyWeighting::facet_over_distance)) - 3 * expected)
          .norm(),
      1e-14);
}

TEST(Laplacian, KuhnCubeIsASixCycle) {
  // The 6 tets of one cube all contain the main diagonal and form a cycle around it: the
  // Laplacian of the 6-cycle, eigenvalues 2 - 2 cos(2 pi k / 6) = {0, 1, 1, 3, 3, 4}. Each
  // interior facet (the diagonal plus a cube vertex) has area sqrt(2)/2 and the centroids of
  // its two tets are sqrt(2)/4 apart: weight 2.
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1), 1, 1, 1);
  Vector expected(6);
  expected << 0, 1, 1, 3, 3, 4;
  EXPECT_LE((sorted_eigenvalues(MaterialSmoothness::laplacian(mesh)) - expected).norm(), 1e-12);
  EXPECT_LE(
      (sorted_eigenvalues(MaterialSmoothness::laplacian(mesh, AdjacencyWeighting::facet_over_distance)) -
       2 * expected)
          .norm(),
      1e-12);
}

TEST(Laplacian, NullSpaceHasOneConstantPerComponent) {
  // Two triangles touching only at a vertex: no shared facet, L = 0 (two components).
  Mesh mesh;
  mesh.rest_positions.resize(5, 2);
  mesh.rest_positions << 0, 0, 1, 0, 0, 1, -1, 0, 0, -1;
  mesh.elements.resize(2, 3);
  mesh.elements << 0, 1, 2, 0, 3, 4;
  mesh.element_regions = Eigen::VectorXi::Zero(2);
  EXPECT_EQ(MaterialSmoothness::laplacian(mesh).nonZeros(), 0);
}

struct Case {
  int dim;
  AdjacencyWeighting weighting;
  bool logarithmic;
};

class MaterialSmoothnessTest : public ::testing::TestWithParam<Case> {};

TEST_P(MaterialSmoothnessTest, DerivativesMatchDifferences) {
  const Case c = GetParam();
  const Mesh mesh = testing::small_mesh(c.dim);
  const int m = mesh.num_elements();
  // The field sits behind three unrelated parameters, to exercise the offset.
  Vector p(3 + 2 * m);
  p << 1.0, -2.0, 3.0, testing::heterogeneous_parameters(mesh, 10.0, 0.3);
  const Vector x = testing::rest_state(mesh) + random_vector(c.dim * mesh.num_vertices(), 2, 0.05);
  const MaterialSmoothness J(mesh, 3, 0.7, {c.weighting, c.logarithmic});
  ASSERT_GT(J.value(x, p), 0.0);

  const Vector s = c.logarithmic ? Vector(p.segment(3, m).array().log()) : Vector(p.segment(3, m));
  EXPECT_NEAR(J.value(x, p), 0.5 * 0.7 * s.dot(MaterialSmoothness::laplacian(mesh, c.weighting) * s), 1e-12);

  Vector dp = testing::relative_direction(p, 31);
  dp.head(3).setZero();
  dp.tail(m).setZero();  // only the smoothed block matters
  const Vector no_dx = Vector::Zero(x.size());
  TAILOR_EXPECT_CHECK(testing::check_gradient_p(J, x, p, dp));
  TAILOR_EXPECT_CHECK(testing::check_hessian(J, x, p, no_dx, dp));
  TAILOR_EXPECT_CHECK(testing::check_residual_jacobians(J, x, p, no_dx, dp));
  testing::expect_least_squares_consistent(J, x, p);
  EXPECT_EQ(J.num_residuals(), element_adjacency(mesh).rows());

  // Only the block is touched, and x plays no part.
  const Vector gp = testing::gradient_p(J, x, p);
  EXPECT_EQ(gp.head(3), Vector::Zero(3));
  EXPECT_EQ(gp.tail(m), Vector::Zero(m));
  EXPECT_EQ(testing::gradient_x(J, x, p), Vector::Zero(x.size()));
  EXPECT_EQ(J.value(x, p), J.value(2.0 * x, p));
}

INSTANTIATE_TEST_SUITE_P(Cases, MaterialSmoothnessTest,
                         ::testing::Values(Case{2, AdjacencyWeighting::unit, false},
                                           Case{3, AdjacencyWeighting::unit, false},
                                           Case{2, AdjacencyWeighting::facet_over_distance, false},
                                           Case{3, AdjacencyWeighting::facet_over_distance, false},
                                           Case{2, AdjacencyWeighting::unit, true},
                                           Case{3, AdjacencyWeighting::unit, true},
                                           Case{2, AdjacencyWeighting::facet_over_distance, true},
                                           Case{3, AdjacencyWeighting::facet_over_distance, true}),
                         [](const ::testing::TestParamInfo<Case>& param_info) {
                           return "dim" + std::to_string(param_info.param.dim) + "_" +
                                  weighting_name(param_info.param.weighting) +
                                  (param_info.param.logarithmic ? "_log" : "");
                         });

TEST(MaterialSmoothness, LogIsScaleInvariantAndVanishesOnConstants) {
  const Mesh mesh = testing::small_mesh(3);
  const Vector x = testing::rest_state(mesh);
  const Vector q = testing::heterogeneous_parameters(mesh, 10.0, 0.3).head(mesh.num_elements());
  const MaterialSmoothness J(mesh, 0, 1.0, {AdjacencyWeighting::unit, true});
  EXPECT_NEAR(J.value(x, q), J.value(x, 1000.0 * q), 1e-12 * J.value(x, q));
  EXPECT_LE(J.value(x, Vector::Constant(mesh.num_elements(), 5.0)), 1e-28);
}

TEST(MaterialSmoothness, RejectsInvalidInput) {
  const Mesh mesh = testing::small_mesh(2);
  const int m = mesh.num_elements();
  EXPECT_THROW(MaterialSmoothness(mesh, -1, 1.0), std::invalid_argument);
  EXPECT_THROW(MaterialSmoothness(mesh, 0, -1.0), std::invalid_argument);
  EXPECT_THROW(MaterialSmoothness(mesh, 0, std::nan("")), std::invalid_argument);
  EXPECT_THROW(MaterialSmoothness(Mesh{}, 0, 1.0), std::invalid_argument);
  Mesh bad = mesh;
  bad.elements.conservativeResize(Eigen::NoChange, 2);
  EXPECT_THROW(MaterialSmoothness(bad, 0, 1.0), std::invalid_argument);

  const MaterialSmoothness J(mesh, 2, 1.0);
  EXPECT_THROW(J.value(Vector(), Vector::Ones(m + 1)), std::invalid_argument);  // block out of range
  Vector p = Vector::Ones(m);
  p[3] = -1.0;
  const MaterialSmoothness log_J(mesh, 0, 1.0, {AdjacencyWeighting::unit, true});
  EXPECT_THROW(log_J.value(Vector(), p), std::domain_error);
}

}  // namespace
}  // namespace tailor::material_smoothness_test
