#pragma once
// Generic (non-polynomial, non-convex) principal-stretch curves for derivative checks, so no
// term can vanish by accident; the ranges put the extreme cases (10x stretch, 0.1x compression,
// inversion) partly into the linear continuations. No test deformation sits on a knot or a range
// end, where the curves are only C2 (C1 at the ends) and differences converge at first order.
#include <cmath>

#include "forward/fem/materials/principal_stretch_curves.hpp"

namespace tailor::test {

inline PrincipalStretchCurves generic_curves() {
  const auto f = [](double s) { return 1.5 * (s - 1) * (s - 1) + 0.3 * std::sin(2 * s); };
  const auto f2 = [](double s) { return 3.0 - 1.2 * std::sin(2 * s); };
  const auto g = [](double t) { return 0.4 * t * t + 0.2 * std::cos(1.5 * t); };
  const auto g2 = [](double t) { return 0.8 - 0.45 * std::cos(1.5 * t); };
  const auto h = [](double J) { return 2.0 * (J - 1) * (J - 1) + 0.5 * std::exp(-J); };
  const auto h2 = [](double J) { return 4.0 + 0.5 * std::exp(-J); };
  return {CubicSpline::approximating(-1.3, 3.0, 11, f, f2), CubicSpline::approximating(-2.0, 5.0, 9, g, g2),
          CubicSpline::approximating(-2.7, 4.0, 10, h, h2)};
}

}  // namespace tailor::test
