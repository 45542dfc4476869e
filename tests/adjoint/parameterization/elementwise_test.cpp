// identity_map, exp_map, bounds_map: values against closed forms, derivatives against
// differences, reverse mode against direct mode.
#include <cmath>

#include "map_checks.hpp"

namespace tailor::elementwise_test {
namespace {

using testing::random_vector;

TEST(IdentityMap, IsTheIdentityWithIdentityJacobian) {
  const auto map = identity_map(5);
  EXPECT_EQ(map->name(), "identity(5)");
  EXPECT_EQ(map->num_design(), 5);
  EXPECT_EQ(map->num_params(), 5);
  const Vector z = random_vector(5, 1);
  EXPECT_EQ(map->apply(z), z);
  EXPECT_EQ(map->jacobian(z), Matrix::Identity(5, 5));
  testing::expect_first_order_consistent(*map, z, false);
  testing::expect_linear_in_z(*map, z);
}

TEST(ExpMap, ValuesAndDerivativesMatchClosedForms) {
  const auto map = exp_map(12);
  EXPECT_EQ(map->name(), "exp(12)");
  const Vector z = random_vector(12, 2, -3.0, 3.0), w = random_vector(12, 3), dz = random_vector(12, 4);
  const Vector p = map->apply(z);
  for (int i = 0; i < 12; ++i) {
    EXPECT_DOUBLE_EQ(p[i], std::exp(z[i]));
    EXPECT_DOUBLE_EQ(map->jacobian_times(z, dz)[i], std::exp(z[i]) * dz[i]);
    EXPECT_DOUBLE_EQ(map->second_derivative_times(z, w, dz)[i], w[i] * std::exp(z[i]) * dz[i]);
  }
  EXPECT_TRUE(map->jacobian(z).isApprox(Matrix(p.asDiagonal()), 1e-15));
}

TEST(ExpMap, DerivativesMatchDifferences) {
  const auto map = exp_map(12);
  const Vector z = random_vector(12, 5, -3.0, 3.0);
  testing::expect_first_order_consistent(*map, z, true);
  testing::expect_second_order_consistent(*map, z);
}

struct BoundsFixture {
  Vector lower = (Vector(4) << -1.0, 0.0, 2.0, 1e3).finished();
  Vector upper = (Vector(4) << 1.0, 1e-3, 5.0, 1e4).finished();
  ParameterizationPtr map = bounds_map(lower, upper);
};

TEST(BoundsMap, MidpointLimitsAndClosedForm) {
  BoundsFixture f;
  EXPECT_EQ(f.map->name(), "bounds(4)");
  EXPECT_TRUE(f.map->apply(Vector::Zero(4)).isApprox((f.lower + f.upper) / 2, 1e-15));
  // Saturation: far out in z the parameters reach the bounds (to round-off), never beyond.
  const Vector high = f.map->apply(Vector::Constant(4, 40.0)), low = f.map->apply(Vector::Constant(4, -40.0));
  for (int i = 0; i < 4; ++i) {
    const double scale = std::abs(f.lower[i]) + std::abs(f.upper[i]);
    EXPECT_NEAR(high[i], f.upper[i], 1e-14 * scale);
    EXPECT_NEAR(low[i], f.lower[i], 1e-14 * scale);
    EXPECT_LE(high[i], f.upper[i]);
    EXPECT_GE(low[i], f.lower[i]);
  }
  // Moderate z stays strictly inside, and p matches lower + (upper - lower)(1 + tanh z)/2.
  const Vector z = random_vector(4, 6, -4.0, 4.0);
  const Vector p = f.map->apply(z);
  for (int i = 0; i < 4; ++i) {
    EXPECT_GT(p[i], f.lower[i]);
    EXPECT_LT(p[i], f.upper[i]);
    EXPECT_NEAR(p[i], f.lower[i] + (f.upper[i] - f.lower[i]) * (1 + std::tanh(z[i])) / 2,
                1e-14 * (std::abs(f.lower[i]) + std::abs(f.upper[i])));
    const double slope = (f.upper[i] - f.lower[i]) / (2 * std::cosh(z[i]) * std::cosh(z[i]));
    EXPECT_NEAR(f.map->jacobian(z)(i, i), slope, 1e-14 * std::abs(slope));
  }
}

TEST(BoundsMap, TailsKeepRelativeAccuracy) {
  // Near a bound, p - lower ~ width e^{2z} and the slope ~ 2 width e^{2z}: both must keep full
  // relative accuracy (1 + tanh z would cancel to zero well before z = -20).
  const auto map = bounds_map(Vector::Zero(1), Vector::Ones(1));
  const Vector z = Vector::Constant(1, -20.0);
  const double e = std::exp(-40.0);
  EXPECT_NEAR(map->apply(z)[0], e / (1 + e), 1e-15 * e);
  const double slope = 0.5 / (std::cosh(20.0) * std::cosh(20.0));
  EXPECT_NEAR(map->jacobian_times(z, Vector::Ones(1))[0], slope, 1e-14 * slope);
  const double curvature = -std::tanh(-20.0) * 2 * slope;  // -tanh(z) sech^2(z) for width 1
  EXPECT_NEAR(map->second_derivative_times(z, Vector::Ones(1), Vector::Ones(1))[0], curvature,
              1e-14 * curvature);
}

TEST(BoundsMap, DerivativesMatchDifferences) {
  BoundsFixture f;
  const Vector z = random_vector(4, 7, -2.0, 2.0);
  testing::expect_first_order_consistent(*f.map, z, true);
  testing::expect_second_order_consistent(*f.map, z);
}

}  // namespace
}  // namespace tailor::elementwise_test
