#include "objectives/tikhonov.hpp"

#include <gtest/gtest.h>

#include "objective_checks.hpp"
#include "../support/fem_fixtures.hpp"

namespace tailor::tikhonov_test {
namespace {

using testing::random_vector;

TEST(Tikhonov, ValueByHand) {
  // p = [9, 1, 2, 3], block [1, 4), prior [0, 0, 1], weights [1, 2, 3]:
  // J = 0.5 * 2 * (1^2 + (2 * 2)^2 + (3 * 2)^2) = 53.
  Vector p(4);
  p << 9, 1, 2, 3;
  const Tikhonov J(1, 3, 2.0, Vector::Unit(3, 2), Vector::LinSpaced(3, 1, 3));
  EXPECT_DOUBLE_EQ(J.value(Vector(), p), 53.0);
  Vector expected(4);
  expected << 0, 2 * 1, 2 * 4 * 2, 2 * 9 * 2;
  EXPECT_EQ(testing::gradient_p(J, Vector(), p), expected);
}

class TikhonovTest : public ::testing::TestWithParam<int> {};

TEST_P(TikhonovTest, DerivativesMatchDifferences) {
  const int dim = GetParam();
  const Mesh mesh = testing::small_mesh(dim);
  const int m = mesh.num_elements();
  const Vector x = testing::rest_state(mesh) + random_vector(dim * mesh.num_vertices(), 4, 0.05);
  const Vector p = testing::heterogeneous_parameters(mesh, 10.0, 0.3);
  // Regularise the Young's moduli towards 8 with random positive weights.
  const Tikhonov J(0, m, 0.3, Vector::Constant(m, 8.0), (random_vector(m, 8).array() + 1.5).matrix());
  const Vector dp = testing::relative_direction(p, 37);
  const Vector no_dx = Vector::Zero(x.size());
  TAILOR_EXPECT_CHECK(testing::check_gradient_p(J, x, p, dp));
  TAILOR_EXPECT_CHECK(testing::check_hessian(J, x, p, no_dx, dp));
  TAILOR_EXPECT_CHECK(testing::check_residual_jacobians(J, x, p, no_dx, dp));
  testing::expect_least_squares_consistent(J, x, p);
  EXPECT_EQ(testing::gradient_x(J, x, p), Vector::Zero(x.size()));
  EXPECT_EQ(testing::gradient_p(J, x, p).tail(m), Vector::Zero(m));  // the Poisson block is not touched
}

INSTANTIATE_TEST_SUITE_P(Dims, TikhonovTest, ::testing::Values(2, 3),
                         [](const ::testing::TestParamInfo<int>& param_info) {
                           return "dim" + std::to_string(param_info.param);
                         });

TEST(Tikhonov, RejectsInvalidInput) {
  const Vector prior = Vector::Zero(3);
  EXPECT_THROW(Tikhonov(-1, 3, 1.0, prior), std::invalid_argument);
  EXPECT_THROW(Tikhonov(0, 0, 1.0, Vector()), std::invalid_argument);
  EXPECT_THROW(Tikhonov(0, 3, -1.0, prior), std::invalid_argument);
  EXPECT_THROW(Tikhonov(0, 3, std::numeric_limits<double>::infinity(), prior), std::invalid_argument);
  EXPECT_THROW(Tikhonov(0, 3, 1.0, Vector::Zero(2)), std::invalid_argument);
  EXPECT_THROW(Tikhonov(0, 3, 1.0, Vector::Constant(3, std::nan(""))), std::invalid_argument);
  EXPECT_THROW(Tikhonov(0, 3, 1.0, prior, Vector::Ones(4)), std::invalid_argument);
  EXPECT_THROW(Tikhonov(0, 3, 1.0, prior, -Vector::Ones(3)), std::invalid_argument);
  const Tikhonov J(2, 3, 1.0, prior);
  EXPECT_THROW(J.value(Vector(), Vector::Zero(4)), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::tikhonov_test
