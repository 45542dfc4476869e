// forward/core/dual2.hpp: every operation of Dual2<N> against central differences of the same
// formula evaluated in doubles (the reference: the definition of the derivative). The operands
// are not plain input variables but general quadratics of three inputs, so each check also
// exercises the second-order chain rule with nonzero incoming gradients and Hessians. Edge cases:
// atan2 next to both axes and on either side of its branch cut, sqrt and log next to 0, division
// by small denominators. The checker is shown to see a wrong second derivative.
#include "forward/core/dual2.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

namespace tailor::dual2_test {
namespace {

using D = Dual2<3>;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// An operand: q(x) = value + gradient . (x - x0) + 1/2 (x - x0)^T hessian (x - x0), evaluated in
// doubles for the reference and as a Dual2 (its exact derivatives at x0) for the operation.
struct Quadratic {
  double value;
  Vec3 gradient;
  Mat3 hessian;

  double at(const Vec3& dx) const { return value + gradient.dot(dx) + 0.5 * dx.dot(hessian * dx); }
  D at_x0() const {
    D d(value);
    d.g = gradient;
    d.h = hessian;
    return d;
  }
};

Quadratic operand(double value, int seed) {
  // Fixed, asymmetric-looking entries so that no cross term vanishes by accident.
  const double s = 0.1 * (seed + 1);
  Quadratic q{value, Vec3(0.7 * s, -0.4 + s, 0.3 - 0.5 * s), Mat3()};
  q.hessian << 0.5 * s, 0.2, -0.1 * s,  //
      0.2, -0.3 + s, 0.25,              //
      -0.1 * s, 0.25, 0.4 - s;
  return q;
}

struct Errors {
  double value = 0.0, gradient = 0.0, hessian = 0.0;
};

// Relative to the reference, or to 1 where the reference vanishes (cos' at 0): the operands'
// derivatives are of order 1, so an absolute error of 1e-9 there is round-off, not a wrong formula.
double relative(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1.0); }
double relative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / std::max(b.norm(), 1.0);
}

// Relative errors of f(a, b) evaluated on Dual2 against central differences with step h in x:
// of the double formula for the gradient, of the Dual2 gradient for the Hessian (checked only
// after the gradient itself agrees with the values).
template <class F>
Errors compare(F f, const Quadratic& a, const Quadratic& b, double h) {
  const D r = f(a.at_x0(), b.at_x0());
  auto value = [&](const Vec3& dx) { return f(a.at(dx), b.at(dx)); };
  auto gradient = [&](const Vec3& dx) {
    // The operands' exact derivatives at x0 + dx: gradient + hessian dx, hessian.
    D ad(a.at(dx)), bd(b.at(dx));
    ad.g = a.gradient + a.hessian * dx;
    ad.h = a.hessian;
    bd.g = b.gradient + b.hessian * dx;
    bd.h = b.hessian;
    return Vec3(f(ad, bd).g);
  };
  Vec3 fd_gradient;
  Mat3 fd_hessian;
  for (int i = 0; i < 3; ++i) {
    const Vec3 e = h * Vec3::Unit(i);
    fd_gradient[i] = (value(e) - value(-e)) / (2.0 * h);
    fd_hessian.col(i) = (gradient(e) - gradient(-e)) / (2.0 * h);
  }
  return {relative(r.v, value(Vec3::Zero())), relative(r.g, fd_gradient), relative(r.h, fd_hessian)};
}

// Unary operations go through the same checker with b ignored.
template <class F>
Errors compare_unary(F f, double a0, double h) {
  return compare([&](const auto& a, const auto&) { return f(a); }, operand(a0, 0), operand(1.0, 1), h);
}

void expect_accurate(const Errors& e, const std::string& what, double tolerance = 1e-7) {
  EXPECT_LT(e.value, 1e-14) << what;
  EXPECT_LT(e.gradient, tolerance) << what;
  EXPECT_LT(e.hessian, tolerance) << what;
}

TEST(Dual2, VariablesAndConstants) {
  const D x = D::variable(2.5, 1);
  EXPECT_EQ(x.v, 2.5);
  EXPECT_EQ(x.g, Vec3(0.0, 1.0, 0.0));
  EXPECT_TRUE(x.h.isZero(0.0));
  const D c = 4.0;
  EXPECT_EQ(c.v, 4.0);
  EXPECT_TRUE(c.g.isZero(0.0));
  EXPECT_TRUE(c.h.isZero(0.0));
  const D defaulted;
  EXPECT_EQ(defaulted.v, 0.0);
  EXPECT_TRUE(defaulted.g.isZero(0.0));
}

TEST(Dual2, ArithmeticOfTwoNumbers) {
  const Quadratic a = operand(1.3, 0), b = operand(-0.7, 1);
  expect_accurate(compare([](const auto& x, const auto& y) { return x + y; }, a, b, 1e-4), "a + b");
  expect_accurate(compare([](const auto& x, const auto& y) { return x - y; }, a, b, 1e-4), "a - b");
  expect_accurate(compare([](const auto& x, const auto& y) { return x * y; }, a, b, 1e-4), "a * b");
  expect_accurate(compare([](const auto& x, const auto& y) { return x / y; }, a, b, 1e-4), "a / b");
  expect_accurate(compare([](const auto& x, const auto&) { return -x; }, a, b, 1e-4), "-a");
  // The same number on both sides: a * a and a / a (= 1, all derivatives zero).
  expect_accurate(compare([](const auto& x, const auto&) { return x * x; }, a, b, 1e-4), "a * a");
  const D one = a.at_x0() / a.at_x0();
  EXPECT_NEAR(one.v, 1.0, 1e-15);
  EXPECT_LT(one.g.norm() + one.h.norm(), 1e-14);
}

TEST(Dual2, DivisionBySmallDenominators) {
  for (const double b0 : {1e-2, -1e-3, 1e-4}) {
    // The denominator's curvature scale is |b0|: steps well inside it.
    const Errors e = compare([](const auto& x, const auto& y) { return x / y; }, operand(0.9, 0),
                             operand(b0, 1), 1e-4 * std::abs(b0));
    expect_accurate(e, "a / b, b = " + std::to_string(b0), 1e-6);
    expect_accurate(compare_unary([](const auto& x) { return 2.0 / x; }, b0, 1e-4 * std::abs(b0)),
                    "2 / a, a = " + std::to_string(b0), 1e-6);
    expect_accurate(compare_unary([](const auto& x) { return reciprocal(x); }, b0, 1e-4 * std::abs(b0)),
                    "reciprocal(a), a = " + std::to_string(b0), 1e-6);
  }
}

TEST(Dual2, MixedWithScalars) {
  const double h = 1e-4;
  expect_accurate(compare_unary([](const auto& x) { return x + 2.0; }, 0.8, h), "a + c");
  expect_accurate(compare_unary([](const auto& x) { return 2.0 + x; }, 0.8, h), "c + a");
  expect_accurate(compare_unary([](const auto& x) { return x - 2.0; }, 0.8, h), "a - c");
  expect_accurate(compare_unary([](const auto& x) { return 2.0 - x; }, 0.8, h), "c - a");
  expect_accurate(compare_unary([](const auto& x) { return x * -3.0; }, 0.8, h), "a * s");
  expect_accurate(compare_unary([](const auto& x) { return -3.0 * x; }, 0.8, h), "s * a");
  expect_accurate(compare_unary([](const auto& x) { return x / 7.0; }, 0.8, h), "a / s");
  expect_accurate(compare_unary([](const auto& x) { return 7.0 / x; }, 0.8, h), "c / a");
}

TEST(Dual2, CompoundAssignment) {
  const Quadratic a = operand(1.1, 0), b = operand(0.6, 1);
  auto chained = [](const auto& x, const auto& y) {
    auto r = x;
    r += y;
    r *= x;
    r -= y;
    r *= 1.5;
    return r;  // 1.5 ((x + y) x - y)
  };
  expect_accurate(compare(chained, a, b, 1e-4), "+=, *=, -=, *= s");
}

TEST(Dual2, ElementaryFunctions) {
  const double h = 1e-4;
  for (const double a0 : {-2.0, -0.3, 0.0, 0.4, 1.7, M_PI}) {
    const std::string at = " at " + std::to_string(a0);
    expect_accurate(compare_unary([](const auto& x) { return sin(x); }, a0, h), "sin" + at);
    expect_accurate(compare_unary([](const auto& x) { return cos(x); }, a0, h), "cos" + at);
    expect_accurate(compare_unary([](const auto& x) { return exp(x); }, a0, h), "exp" + at);
  }
  expect_accurate(compare_unary([](const auto& x) { return exp(x); }, 20.0, h), "exp at 20");
  for (const double a0 : {0.05, 1.0, 30.0}) {
    const std::string at = " at " + std::to_string(a0);
    expect_accurate(compare_unary([](const auto& x) { return sqrt(x); }, a0, 1e-4 * a0), "sqrt" + at);
    expect_accurate(compare_unary([](const auto& x) { return log(x); }, a0, 1e-4 * a0), "log" + at);
  }
}

TEST(Dual2, SqrtAndLogNearZero) {
  // Derivatives grow like a^(-1/2), a^(-3/2) (sqrt) and 1/a, 1/a^2 (log); steps scale with a.
  for (const double a0 : {1e-4, 1e-8}) {
    const std::string at = " at " + std::to_string(a0);
    expect_accurate(compare_unary([](const auto& x) { return sqrt(x); }, a0, 1e-4 * a0), "sqrt" + at, 1e-6);
    expect_accurate(compare_unary([](const auto& x) { return log(x); }, a0, 1e-4 * a0), "log" + at, 1e-6);
  }
  // At 0 itself sqrt is not differentiable: the derivatives are infinite, never a finite guess.
  const D s = sqrt(D::variable(0.0, 0));
  EXPECT_EQ(s.v, 0.0);
  EXPECT_TRUE(std::isinf(s.g[0]));
}

TEST(Dual2, Atan2InEveryQuadrantAndNearTheAxes) {
  struct Case {
    double y, x;
  };
  for (const Case c : {Case{0.6, 0.8}, Case{0.6, -0.8}, Case{-0.6, -0.8}, Case{-0.6, 0.8},  // quadrants
                       Case{1e-3, 1.0}, Case{-1e-3, 1.0},                                   // near +x
                       Case{1.0, 1e-3}, Case{1.0, -1e-3}, Case{-1.0, 1e-3},                 // near +-y
                       Case{1e-3, -1.0}, Case{-1e-3, -1.0}}) {  // either side of the branch cut
    const std::string at = " at (y, x) = (" + std::to_string(c.y) + ", " + std::to_string(c.x) + ")";
    // Steps well inside the distance to the nearest axis, so no difference crosses the cut.
    const double h = 1e-4 * std::min(std::abs(c.x), std::abs(c.y));
    expect_accurate(compare([](const auto& y, const auto& x) { return atan2(y, x); }, operand(c.y, 0),
                            operand(c.x, 1), h),
                    "atan2" + at, 1e-6);
  }
}

TEST(Dual2, ChainWithUserSuppliedDerivatives) {
  // chain(a, f, f', f'') for a function the type does not provide: here f = a^3.
  auto cube = [](const auto& x) {
    if constexpr (std::is_same_v<std::decay_t<decltype(x)>, double>) {
      return x * x * x;
    } else {
      return chain(x, x.v * x.v * x.v, 3.0 * x.v * x.v, 6.0 * x.v);
    }
  };
  expect_accurate(compare_unary(cube, 1.3, 1e-4), "chain(a^3)");
}

TEST(Dual2, ACompositeFormula) {
  // A rod-like angle: atan2 of a cross- and a dot-product-like pair, scaled by a length.
  auto angle = [](const auto& a, const auto& b) {
    const auto length = sqrt(a * a + b * b + 1.0);
    return length * atan2(a * b - 0.3, a + 2.0 * b) + exp(-a) / (1.0 + b * b);
  };
  expect_accurate(compare(angle, operand(0.4, 0), operand(0.9, 1), 1e-4), "composite");
}

TEST(Dual2, TheCheckSeesAWrongSecondDerivative) {
  // sin with the sign of f'' flipped, and with f' off by 1%: the checker must report both.
  auto wrong_curvature = [](const auto& x) {
    if constexpr (std::is_same_v<std::decay_t<decltype(x)>, double>) {
      return std::sin(x);
    } else {
      return chain(x, std::sin(x.v), std::cos(x.v), std::sin(x.v));
    }
  };
  const Errors curvature = compare_unary(wrong_curvature, 0.7, 1e-4);
  EXPECT_LT(curvature.gradient, 1e-7);
  EXPECT_GT(curvature.hessian, 1e-2);
  auto wrong_slope = [](const auto& x) {
    if constexpr (std::is_same_v<std::decay_t<decltype(x)>, double>) {
      return std::sin(x);
    } else {
      return chain(x, std::sin(x.v), 1.01 * std::cos(x.v), -std::sin(x.v));
    }
  };
  EXPECT_GT(compare_unary(wrong_slope, 0.7, 1e-4).gradient, 1e-3);
}

}  // namespace
}  // namespace tailor::dual2_test
