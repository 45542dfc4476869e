#pragma once
// The elastica of a tip-loaded cantilever by elliptic integrals (Bisshopp & Drucker, Q. Appl.
// Math. 3 (1945) 272): the reference of the rod validation tests, in C++
// (tests/forward/rods/rod_validation_test.cpp) and through the scene parser
// (tests/problems/rods/rod_elastica_scene_test.cpp).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>

namespace tailor::testing {

// The elastica of a cantilever (clamped at s = 0 along +x, length L, bending stiffness EI) under
// a dead tip load P along -y: with alpha = P L^2 / EI, k^2 = (1 + sin theta_tip) / 2 and
// sin phi0 = 1 / (k sqrt 2), the tip rotation solves sqrt(alpha) = K(k) - F(phi0, k); then
//   x_tip = L sqrt(2 sin theta_tip / alpha),  deflection = L - 2 sqrt(EI / P) (E(k) - E(phi0, k)).
inline Eigen::Vector2d elastica_tip(double alpha, double L) {
  auto length_residual = [&](double k) {
    const double phi0 = std::asin(1.0 / (k * std::sqrt(2.0)));
    return std::comp_ellint_1(k) - std::ellint_1(k, phi0) - std::sqrt(alpha);
  };
  double lo = 1.0 / std::sqrt(2.0) + 1e-15, hi = 1.0 - 1e-15;  // residual rises from -sqrt(alpha)
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (length_residual(mid) < 0.0 ? lo : hi) = mid;
  }
  const double k = 0.5 * (lo + hi);
  EXPECT_LT(std::abs(length_residual(k)), 1e-12);
  const double phi0 = std::asin(1.0 / (k * std::sqrt(2.0)));
  const double sin_tip = 2.0 * k * k - 1.0;
  const double x_tip = L * std::sqrt(2.0 * sin_tip / alpha);
  const double deflection = L - 2.0 * L / std::sqrt(alpha) * (std::comp_ellint_2(k) - std::ellint_2(k, phi0));
  return {x_tip, deflection};
}

}  // namespace tailor::testing
