// CubicSpline: exact reproduction of cubic polynomials (reference: the B-spline quasi-interpolant
// c_k = p(t_k) - h^2/6 p''(t_k) reproduces cubics, de Boor, "A Practical Guide to Splines"),
// linear continuation outside the range, control-value linearity, and the divided difference
// of the slope without cancellation.
#include "forward/fem/materials/cubic_spline.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace tailor::cubic_spline_test {
namespace {

double cubic(double x) { return 0.7 - 1.3 * x + 0.4 * x * x + 0.25 * x * x * x; }
double cubic1(double x) { return -1.3 + 0.8 * x + 0.75 * x * x; }
double cubic2(double x) { return 0.8 + 1.5 * x; }

TEST(CubicSpline, ReproducesCubicsInsideTheRange) {
  const CubicSpline s = CubicSpline::approximating(-0.5, 2.5, 7, cubic, cubic2);
  for (double x = -0.5; x <= 2.5; x += 0.0137) {
    const auto y = s.evaluate(x);
    EXPECT_NEAR(y.value, cubic(x), 1e-13);
    EXPECT_NEAR(y.slope, cubic1(x), 1e-12);
    EXPECT_NEAR(y.curvature, cubic2(x), 1e-11);
  }
}

TEST(CubicSpline, ContinuesLinearlyOutsideTheRange) {
  const CubicSpline s = CubicSpline::approximating(-0.5, 2.5, 7, cubic, cubic2);
  for (double x : {-3.0, -0.6, 2.6, 10.0}) {
    const double end = x < 0 ? -0.5 : 2.5;
    const auto y = s.evaluate(x);
    EXPECT_NEAR(y.value, cubic(end) + cubic1(end) * (x - end), 1e-11);
    EXPECT_NEAR(y.slope, cubic1(end), 1e-12);
    EXPECT_EQ(y.curvature, 0.0);
  }
}

TEST(CubicSpline, BasisIsTheDerivativeWithRespectToControls) {
  Eigen::VectorXd c(8);
  c << 0.3, -0.2, 1.1, 0.7, -0.4, 0.9, 0.2, -1.0;
  const CubicSpline s(0.0, 1.0, 5, c);
  for (double x : {-0.7, 0.0, 0.13, 0.5, 0.99, 1.0, 1.8}) {
    const auto b = s.basis(x);
    for (int k = 0; k < 8; ++k) {
      Eigen::VectorXd e = Eigen::VectorXd::Zero(8);
      e[k] = 1.0;
      const CubicSpline unit(0.0, 1.0, 5, e);
      const auto y = unit.evaluate(x);
      const int r = k - b.first;
      const bool in = r >= 0 && r < 4;
      EXPECT_NEAR(y.value, in ? b.value[r] : 0.0, 1e-14);
      EXPECT_NEAR(y.slope, in ? b.slope[r] : 0.0, 1e-13);
      EXPECT_NEAR(y.curvature, in ? b.curvature[r] : 0.0, 1e-12);
    }
    // Slope and curvature are the x-derivatives of value and slope (central differences).
    const double h = 1e-6;
    if (std::abs(x) > 1e-3 && std::abs(x - 1.0) > 1e-3) {
      EXPECT_NEAR(s.evaluate(x).slope, (s.evaluate(x + h).value - s.evaluate(x - h).value) / (2 * h), 1e-7);
      EXPECT_NEAR(s.evaluate(x).curvature, (s.evaluate(x + h).slope - s.evaluate(x - h).slope) / (2 * h),
                  1e-6);
    }
  }
}

TEST(CubicSpline, SlopeDividedDifferenceIsExactAndStable) {
  Eigen::VectorXd c(8);
  c << 0.3, -0.2, 1.1, 0.7, -0.4, 0.9, 0.2, -1.0;
  const CubicSpline s(0.0, 1.0, 5, c);
  // Well separated points (same piece, across knots, across the range ends): the quotient.
  const double pairs[][2] = {{0.31, 0.27}, {0.05, 0.93}, {-0.5, 0.44}, {0.7, 1.6}, {-0.4, 1.3}, {-0.9, -0.2}};
  for (const auto& ab : pairs) {
    const double a = ab[0], b = ab[1];
    EXPECT_NEAR(s.slope_divided_difference(a, b), (s.evaluate(a).slope - s.evaluate(b).slope) / (a - b),
                1e-12);
    EXPECT_EQ(s.slope_divided_difference(a, b), s.slope_divided_difference(b, a));
  }
  // Nearly coincident points, also straddling a knot (0.4): the limit y''(a), not cancellation.
  for (double a : {0.33, 0.4, 0.71})
    for (double gap : {1e-8, 1e-12, 0.0}) {
      const double d = s.slope_divided_difference(a + gap, a - gap);
      EXPECT_NEAR(d, s.evaluate(a).curvature, 1e-6 * (1.0 + std::abs(d))) << a << " " << gap;
    }
}

// Why the divided difference is not the plain quotient: at a gap of 1e-12 the quotient of two
// slopes loses ~12 digits to cancellation, the piecewise mean does not.
TEST(CubicSpline, PlainQuotientCancelsWhereTheDividedDifferenceDoesNot) {
  Eigen::VectorXd c(8);
  c << 0.3, -0.2, 1.1, 0.7, -0.4, 0.9, 0.2, -1.0;
  const CubicSpline s(0.0, 1.0, 5, c);
  const double a = 0.33, b = 0.33 - 1e-12, exact = s.evaluate(a - 0.5e-12).curvature;
  const double plain = (s.evaluate(a).slope - s.evaluate(b).slope) / (a - b);
  EXPECT_GT(std::abs(plain - exact), 1e-6 * std::abs(exact));
  EXPECT_LT(std::abs(s.slope_divided_difference(a, b) - exact), 1e-12 * std::abs(exact));
}

TEST(CubicSpline, RejectsBadInput) {
  EXPECT_THROW(CubicSpline(1.0, 1.0, 3, Eigen::VectorXd::Zero(6)), std::invalid_argument);
  EXPECT_THROW(CubicSpline(0.0, 1.0, 0, Eigen::VectorXd::Zero(3)), std::invalid_argument);
  EXPECT_THROW(CubicSpline(0.0, 1.0, 3, Eigen::VectorXd::Zero(5)), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::cubic_spline_test
