// The monotone cubic used for nonlinear damping curves: interpolation, monotonicity and range
// (the Fritsch-Carlson property), constant extension, and its derivatives in t and in the
// control values against central differences.
#include "forward/dynamics/monotone_spline.hpp"

#include <gtest/gtest.h>

#include "adjoint/derivative_check.hpp"

namespace tailor::monotone_spline_test {
namespace {

TEST(MonotoneCubic, InterpolatesAndPreservesMonotonicity) {
  Vector t(5), y(5);
  t << 0.0, 0.1, 0.15, 0.6, 1.0;
  y << 0.1, 0.1, 2.0, 2.2, 6.0;  // flat, steep, flat-ish, steep: an ordinary cubic overshoots
  const MonotoneCubic s(t);
  for (int k = 0; k < 5; ++k) EXPECT_NEAR(s.evaluate(y, t[k]), y[k], 1e-14);
  double previous = s.evaluate(y, -1.0);
  EXPECT_EQ(previous, y[0]);
  for (int i = 1; i <= 2000; ++i) {
    const double value = s.evaluate(y, -0.1 + 1.2 * i / 2000.0);
    EXPECT_GE(value, previous - 1e-14);
    EXPECT_GE(value, y.minCoeff() - 1e-14);
    EXPECT_LE(value, y.maxCoeff() + 1e-14);
    previous = value;
  }
  EXPECT_EQ(s.evaluate(y, 7.0), y[4]);
  // One knot: a constant.
  const MonotoneCubic c(Vector::Constant(1, 0.3));
  Vector g;
  EXPECT_EQ(c.evaluate(Vector::Constant(1, 2.5), 10.0, nullptr, &g), 2.5);
  EXPECT_EQ(g[0], 1.0);
}

TEST(MonotoneCubic, DerivativesInPositionAndControls) {
  Vector t(4), y(4);
  t << 0.0, 0.3, 0.5, 1.2;
  y << 0.5, 1.0, 3.0, 3.5;
  const MonotoneCubic s(t);
  DerivativeCheckOptions o;
  o.initial_step = 1e-3;
  for (double at : {0.05, 0.31, 0.47, 0.9}) {
    double slope = 0.0;
    Vector gy;
    s.evaluate(y, at, &slope, &gy);
    const auto f_t = [&](double h) { return Vector::Constant(1, s.evaluate(y, at + h)); };
    const DerivativeCheck ct = check_directional_derivative("slope", f_t, Vector::Constant(1, slope), o);
    EXPECT_TRUE(ct.passed) << at << " " << ct.message;
    const Vector dy = Vector::LinSpaced(4, 0.3, -0.7);
    const auto f_y = [&](double h) { return Vector::Constant(1, s.evaluate(y + h * dy, at)); };
    const DerivativeCheck cy =
        check_directional_derivative("controls", f_y, Vector::Constant(1, gy.dot(dy)), o);
    EXPECT_TRUE(cy.passed) << at << " " << cy.message;
    // A corrupted control gradient is rejected.
    const DerivativeCheck bad =
        check_directional_derivative("corrupted", f_y, Vector::Constant(1, 1.01 * gy.dot(dy)), o);
    EXPECT_FALSE(bad.passed);
  }
}

TEST(MonotoneCubic, RejectsBadKnots) {
  Vector t(3);
  t << 0.0, 0.5, 0.5;
  EXPECT_THROW(MonotoneCubic{t}, std::invalid_argument);
  EXPECT_THROW(MonotoneCubic{Vector()}, std::invalid_argument);
  const MonotoneCubic s(Vector::LinSpaced(3, 0, 1));
  EXPECT_THROW(s.evaluate(Vector::Zero(2), 0.5), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::monotone_spline_test
