// Lame parameters from Young's modulus and Poisson's ratio (isotropic elasticity):
//   lambda = E nu / ((1 + nu)(1 - 2 nu)),   mu = E / (2 (1 + nu)).
// Plane strain uses the same relations (the 3D material with eps_33 = 0).
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "forward/core/format_number.hpp"
#include "forward/fem/material.hpp"
#include "forward/fem/parameter_refused.hpp"

namespace tailor {
namespace {

void check_young_poisson(double youngs_modulus, double poisson_ratio) {
  // Written so that NaN fails both checks.
  if (!(youngs_modulus > 0.0) || !std::isfinite(youngs_modulus))
    throw ParameterRefused("Young's modulus must be finite and > 0, got E = " +
                                format_number(youngs_modulus, "%.17g"));
  if (!(poisson_ratio > -1.0 && poisson_ratio < 0.5))
    throw ParameterRefused("Poisson's ratio must lie in (-1, 0.5), got nu = " +
                                format_number(poisson_ratio, "%.17g"));
}

}  // namespace

LameParameters lame_from_young_poisson(double youngs_modulus, double poisson_ratio) {
  check_young_poisson(youngs_modulus, poisson_ratio);
  const double E = youngs_modulus, nu = poisson_ratio;
  return {E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))};
}

Eigen::Matrix2d lame_jacobian(double youngs_modulus, double poisson_ratio) {
  check_young_poisson(youngs_modulus, poisson_ratio);
  const double E = youngs_modulus, nu = poisson_ratio;
  // g = (1 + nu)(1 - 2 nu) = 1 - nu - 2 nu^2, g' = -1 - 4 nu,
  // d(nu / g)/dnu = (g - nu g') / g^2 = (1 + 2 nu^2) / g^2.
  const double g = (1.0 + nu) * (1.0 - 2.0 * nu);
  Eigen::Matrix2d J;
  J(0, 0) = nu / g;
  J(0, 1) = E * (1.0 + 2.0 * nu * nu) / (g * g);
  J(1, 0) = 1.0 / (2.0 * (1.0 + nu));
  J(1, 1) = -E / (2.0 * (1.0 + nu) * (1.0 + nu));
  return J;
}

}  // namespace tailor
