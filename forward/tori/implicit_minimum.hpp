#pragma once
// The derivatives of d = sqrt(m(y)), m(y) = min_u f(u, y), at a non-degenerate minimizer (f_u = 0,
// f_uu positive definite), by the implicit function theorem:
//   dm/dy = f_y,   d2m/dy2 = f_yy - f_yu f_uu^-1 f_uy,
// then the chain rule of the square root. f is a second-order jet over (u, y), the U inner
// variables first. Shared by the core-circle distance (torus_distance.cpp, u the two core
// angles) and the surface distance of elliptic tubes (elliptic_distance.cpp, u the four surface
// parameters). implicit_correction = false drops the f_yu f_uu^-1 f_uy term (a deliberately
// wrong Hessian, for the tests that show the derivative check catches it).
#include <Eigen/Dense>

namespace tailor::tori {

template <int U, int Y, typename Jet>
void sqrt_minimum_derivatives(const Jet& f, double d, bool implicit_correction, Eigen::Matrix<double, Y, 1>& gradient,
                              Eigen::Matrix<double, Y, Y>& hessian) {
  const Eigen::Matrix<double, U, U> Huu = f.h.template topLeftCorner<U, U>();
  const Eigen::Matrix<double, U, Y> Huy = f.h.template topRightCorner<U, Y>();
  const Eigen::Matrix<double, Y, 1> g2 = f.g.template tail<Y>();
  Eigen::Matrix<double, Y, Y> H2 = f.h.template bottomRightCorner<Y, Y>();
  if (implicit_correction) H2 -= Huy.transpose() * Huu.ldlt().solve(Huy);
  gradient = g2 / (2.0 * d);
  hessian = H2 / (2.0 * d) - g2 * g2.transpose() / (4.0 * d * d * d);
}

}  // namespace tailor::tori
