#pragma once
// Derivative checks for Objective implementations, built on check_directional_derivative:
// every analytic directional derivative is compared with central differences of the quantity
// it differentiates (value -> gradients -> Hessian products; residuals -> Jacobians).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "adjoint/derivative_check.hpp"
#include "objectives/objective.hpp"

namespace tailor::testing {

inline Vector random_vector(Eigen::Index n, unsigned seed, double scale = 1.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vector v(n);
  for (Eigen::Index i = 0; i < n; ++i) v[i] = scale * u(rng);
  return v;
}

// q_i = |p_i| u_i, u_i uniform in [-1, 1]: a relative perturbation of every parameter.
inline Vector relative_direction(const Vector& p, unsigned seed) {
  return p.cwiseAbs().cwiseProduct(random_vector(p.size(), seed));
}

inline Vector scalar(double v) { return Vector::Constant(1, v); }

inline Vector gradient_x(const Objective& J, const Vector& x, const Vector& p) {
  Vector g = Vector::Zero(x.size());
  J.add_gradient_x(x, p, g);
  return g;
}

inline Vector gradient_p(const Objective& J, const Vector& x, const Vector& p) {
  Vector g = Vector::Zero(p.size());
  J.add_gradient_p(x, p, g);
  return g;
}

// dJ/dx . dx vs differences of J(x + t dx, p).
inline DerivativeCheck check_gradient_x(const Objective& J, const Vector& x, const Vector& p, const Vector& dx,
                                        const DerivativeCheckOptions& options = {}) {
  return check_directional_derivative(
      "gradient_x", [&](double t) { return scalar(J.value(x + t * dx, p)); }, scalar(gradient_x(J, x, p).dot(dx)),
      options);
}

// dJ/dp . dp vs differences of J(x, p + t dp).
inline DerivativeCheck check_gradient_p(const Objective& J, const Vector& x, const Vector& p, const Vector& dp,
                                        const DerivativeCheckOptions& options = {}) {
  return check_directional_derivative(
      "gradient_p", [&](double t) { return scalar(J.value(x, p + t * dp)); }, scalar(gradient_p(J, x, p).dot(dp)),
      options);
}

// [J_xx dx + J_xp dp; J_px dx + J_pp dp] vs differences of [dJ/dx; dJ/dp] along (dx, dp).
inline DerivativeCheck check_hessian(const Objective& J, const Vector& x, const Vector& p, const Vector& dx,
                                     const Vector& dp, const DerivativeCheckOptions& options = {}) {
  const auto n = x.size();
  auto stacked = [&](double t) {
    const Vector xt = x + t * dx, pt = p + t * dp;
    Vector g(n + pt.size());
    g << gradient_x(J, xt, pt), gradient_p(J, xt, pt);
    return g;
  };
  // A term whose product is checked must also say it has one, or the adjoint layer never asks.
  EXPECT_TRUE(J.has_second_derivatives()) << J.name();
  Vector out_x = Vector::Zero(n), out_p = Vector::Zero(p.size());
  J.add_hessian_times(x, p, dx, dp, out_x, out_p);
  Vector analytic(n + p.size());
  analytic << out_x, out_p;
  return check_directional_derivative("hessian_times", stacked, analytic, options);
}

// dr/dx dx + dr/dp dp vs differences of r(x + t dx, p + t dp).
inline DerivativeCheck check_residual_jacobians(const Objective& J, const Vector& x, const Vector& p, const Vector& dx,
                                                const Vector& dp, const DerivativeCheckOptions& options = {}) {
  Vector r;
  SparseMatrix jx, jp;
  J.residuals(x, p, r, &jx, &jp);
  EXPECT_EQ(r.size(), J.num_residuals());
  EXPECT_EQ(jx.rows(), J.num_residuals());
  EXPECT_EQ(jx.cols(), x.size());
  EXPECT_EQ(jp.rows(), J.num_residuals());
  EXPECT_EQ(jp.cols(), p.size());
  const Vector analytic = jx * dx + jp * dp;
  return check_directional_derivative(
      "residual_jacobians",
      [&](double t) {
        Vector rt;
        J.residuals(x + t * dx, p + t * dp, rt, nullptr, nullptr);
        return rt;
      },
      analytic, options);
}

// J = 1/2 ||r||^2, and the gradients equal the Gauss-Newton expressions J_r^T r.
inline void expect_least_squares_consistent(const Objective& J, const Vector& x, const Vector& p) {
  ASSERT_TRUE(J.is_least_squares());
  Vector r;
  SparseMatrix jx, jp;
  J.residuals(x, p, r, &jx, &jp);
  const double value = J.value(x, p);
  EXPECT_NEAR(0.5 * r.squaredNorm(), value, 1e-12 * std::max(1.0, std::abs(value)));
  const Vector gx = gradient_x(J, x, p), gp = gradient_p(J, x, p);
  const Vector gn_x = jx.transpose() * r, gn_p = jp.transpose() * r;
  EXPECT_LE((gn_x - gx).norm(), 1e-10 * std::max(1.0, gx.norm()));
  EXPECT_LE((gn_p - gp).norm(), 1e-10 * std::max(1.0, gp.norm()));
}

#define TAILOR_EXPECT_CHECK(check_expr)                                  \
  do {                                                                   \
    const ::tailor::DerivativeCheck _c = (check_expr);                   \
    EXPECT_TRUE(_c.passed) << _c.quantity << ": " << _c.message;         \
  } while (0)

}  // namespace tailor::testing
