#include "objectives/target_positions.hpp"

#include <gtest/gtest.h>

#include "objective_checks.hpp"
#include "../support/fem_fixtures.hpp"

namespace tailor::target_positions_test {
namespace {

using testing::random_vector;

struct Scene {
  Mesh mesh;
  Vector x, p;
  std::vector<int> vertices;
  Matrix targets;
  Vector weights;
};

Scene make_setup(int dim) {
  Scene s;
  s.mesh = testing::small_mesh(dim);
  s.x = testing::rest_state(s.mesh) + random_vector(dim * s.mesh.num_vertices(), 11, 0.05);
  s.p = testing::heterogeneous_parameters(s.mesh, 10.0, 0.3);
  s.vertices = {1, 4, s.mesh.num_vertices() - 1};
  s.targets = testing::rest_state(s.mesh).head(3 * dim).reshaped(dim, 3).transpose();  // any positions
  s.targets.array() += 0.3;
  s.weights = Vector::LinSpaced(3, 0.5, 2.0);
  return s;
}

class TargetPositionsTest : public ::testing::TestWithParam<int> {};

TEST_P(TargetPositionsTest, DerivativesMatchDifferences) {
  const Scene s = make_setup(GetParam());
  const TargetPositions J(GetParam(), s.vertices, s.targets, s.weights);
  const Vector dx = random_vector(s.x.size(), 5);
  const Vector none = Vector::Zero(s.p.size());
  TAILOR_EXPECT_CHECK(testing::check_gradient_x(J, s.x, s.p, dx));
  TAILOR_EXPECT_CHECK(testing::check_hessian(J, s.x, s.p, dx, none));
  TAILOR_EXPECT_CHECK(testing::check_residual_jacobians(J, s.x, s.p, dx, none));
  testing::expect_least_squares_consistent(J, s.x, s.p);
  // No dependence on p: the p-gradient is untouched and the value does not move.
  EXPECT_EQ(testing::gradient_p(J, s.x, s.p), Vector::Zero(s.p.size()));
  EXPECT_EQ(J.value(s.x, s.p), J.value(s.x, 2.0 * s.p));
}

TEST_P(TargetPositionsTest, ValueByHand) {
  const Scene s = make_setup(GetParam());
  const int dim = GetParam();
  const TargetPositions J(dim, s.vertices, s.targets, s.weights);
  double expected = 0;
  for (int i = 0; i < 3; ++i)
    expected += 0.5 * s.weights[i] * (s.x.segment(dim * s.vertices[i], dim) - s.targets.row(i).transpose()).squaredNorm();
  EXPECT_NEAR(J.value(s.x, s.p), expected, 1e-14);
  EXPECT_EQ(J.num_residuals(), 3 * dim);
  // Zero at the targets.
  Vector at_target = s.x;
  for (int i = 0; i < 3; ++i) at_target.segment(dim * s.vertices[i], dim) = s.targets.row(i).transpose();
  EXPECT_EQ(J.value(at_target, s.p), 0.0);
}

TEST_P(TargetPositionsTest, DisplacementsAreRelativeToRest) {
  const Scene s = make_setup(GetParam());
  const int dim = GetParam();
  const Matrix u = random_vector(3 * dim, 7, 0.1).reshaped(3, dim);
  const TargetPositions J = TargetPositions::displacements(s.mesh, s.vertices, u, s.weights);
  double expected = 0;
  for (int i = 0; i < 3; ++i) {
    const int v = s.vertices[i];
    const Vector displacement = s.x.segment(dim * v, dim) - s.mesh.rest_positions.row(v).transpose();
    expected += 0.5 * s.weights[i] * (displacement - u.row(i).transpose()).squaredNorm();
  }
  EXPECT_NEAR(J.value(s.x, s.p), expected, 1e-14);
  const Vector dx = random_vector(s.x.size(), 6);
  TAILOR_EXPECT_CHECK(testing::check_gradient_x(J, s.x, s.p, dx));
  TAILOR_EXPECT_CHECK(testing::check_hessian(J, s.x, s.p, dx, Vector::Zero(s.p.size())));
  testing::expect_least_squares_consistent(J, s.x, s.p);
}

INSTANTIATE_TEST_SUITE_P(Dims, TargetPositionsTest, ::testing::Values(2, 3),
                         [](const ::testing::TestParamInfo<int>& param_info) {
                           return "dim" + std::to_string(param_info.param);
                         });

TEST(TargetPositions, RejectsInvalidInput) {
  const Matrix t = Matrix::Zero(2, 3);
  EXPECT_THROW(TargetPositions(0, {0, 1}, t), std::invalid_argument);
  EXPECT_THROW(TargetPositions(3, {}, Matrix(0, 3)), std::invalid_argument);
  EXPECT_THROW(TargetPositions(3, {0, 0}, t), std::invalid_argument);       // duplicate vertex
  EXPECT_THROW(TargetPositions(3, {-1, 2}, t), std::invalid_argument);      // negative index
  EXPECT_THROW(TargetPositions(3, {0, 1}, Matrix::Zero(2, 2)), std::invalid_argument);  // wrong shape
  Matrix nan = t;
  nan(1, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(TargetPositions(3, {0, 1}, nan), std::invalid_argument);
  EXPECT_THROW(TargetPositions(3, {0, 1}, t, Vector::Ones(3)), std::invalid_argument);  // weights size
  EXPECT_THROW(TargetPositions(3, {0, 1}, t, Vector::Constant(2, -1.0)), std::invalid_argument);
  const Mesh mesh = testing::small_mesh(3);
  EXPECT_THROW(TargetPositions::displacements(mesh, {0, mesh.num_vertices()}, t), std::invalid_argument);
  // A state that does not hold the selected vertex.
  const TargetPositions J(3, {0, 5}, t);
  EXPECT_THROW(J.value(Vector::Zero(15), Vector()), std::invalid_argument);
  EXPECT_THROW(J.value(Vector::Zero(19), Vector()), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::target_positions_test
