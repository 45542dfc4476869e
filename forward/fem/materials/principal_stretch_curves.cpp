#include "forward/fem/materials/principal_stretch_curves.hpp"

#include <stdexcept>

namespace tailor {
namespace {

CubicSpline zero_spline(const SplineGrid& g) {
  return CubicSpline(g.lower, g.upper, g.intervals, Eigen::VectorXd::Zero(g.intervals + 3));
}

// Quasi-interpolant of a polynomial given by its value and second derivative (exact up to cubics).
CubicSpline approximate(const SplineGrid& g, double (*value)(double, const double*),
                        double (*curvature)(double, const double*), const double* coefficients) {
  return CubicSpline::approximating(
      g.lower, g.upper, g.intervals, [&](double x) { return value(x, coefficients); },
      [&](double x) { return curvature(x, coefficients); });
}

}  // namespace

int PrincipalStretchCurves::num_controls() const {
  return uniaxial.num_controls() + biaxial.num_controls() + volumetric.num_controls();
}

Eigen::VectorXd PrincipalStretchCurves::controls() const {
  Eigen::VectorXd c(num_controls());
  c << uniaxial.controls(), biaxial.controls(), volumetric.controls();
  return c;
}

void PrincipalStretchCurves::set_controls(const Eigen::Ref<const Eigen::VectorXd>& c) {
  if (c.size() != num_controls())
    throw std::invalid_argument("PrincipalStretchCurves: expected " + std::to_string(num_controls()) +
                                " control values, got " + std::to_string(c.size()));
  const int nf = uniaxial.num_controls(), ng = biaxial.num_controls(), nh = volumetric.num_controls();
  uniaxial.set_controls(c.segment(0, nf));
  biaxial.set_controls(c.segment(nf, ng));
  volumetric.set_controls(c.segment(nf + ng, nh));
}

PrincipalStretchCurves zero_curves(const PrincipalStretchGrids& grids) {
  return {zero_spline(grids.uniaxial), zero_spline(grids.biaxial), zero_spline(grids.volumetric)};
}

PrincipalStretchCurves principal_stretch_preset(SplinePreset preset, const LameParameters& lame,
                                                const PrincipalStretchGrids& grids) {
  const double la = lame.lambda, mu = lame.mu;
  PrincipalStretchCurves c = zero_curves(grids);
  // Each curve is a polynomial; coefficients k[0..4] of 1, x, x^2, x^3, x^4.
  const auto poly = [](double x, const double* k) {
    return k[0] + x * (k[1] + x * (k[2] + x * (k[3] + x * k[4])));
  };
  const auto poly2 = [](double x, const double* k) {
    return 2.0 * k[2] + x * (6.0 * k[3] + 12.0 * x * k[4]);
  };
  switch (preset) {
    case SplinePreset::corotated: {
      // f = (mu + la/2)(s - 1)^2 - 2 la s + la, g = la t.
      const double a = mu + 0.5 * la;
      const double f[5] = {a + la, -2.0 * a - 2.0 * la, a, 0.0, 0.0};
      const double g[5] = {0.0, la, 0.0, 0.0, 0.0};
      c.uniaxial = approximate(grids.uniaxial, poly, poly2, f);
      c.biaxial = approximate(grids.biaxial, poly, poly2, g);
      break;
    }
    case SplinePreset::stvk: {
      // f = la/8 (s^4 - 6 s^2 + 3) + mu/4 (s^4 - 2 s^2 + 1), g = la/4 t^2.
      const double f[5] = {3.0 * la / 8.0 + mu / 4.0, 0.0, -6.0 * la / 8.0 - mu / 2.0, 0.0,
                           la / 8.0 + mu / 4.0};
      const double g[5] = {0.0, 0.0, la / 4.0, 0.0, 0.0};
      c.uniaxial = approximate(grids.uniaxial, poly, poly2, f);
      c.biaxial = approximate(grids.biaxial, poly, poly2, g);
      break;
    }
    case SplinePreset::neo_hookean: {
      // f = mu/2 (s^2 - 1), h = la'/2 ((J - alpha)^2 - (1 - alpha)^2) = la'/2 (J^2 - 1) - la' alpha (J - 1).
      const double ls = la + mu, alpha = 1.0 + mu / ls;
      const double f[5] = {-0.5 * mu, 0.0, 0.5 * mu, 0.0, 0.0};
      const double h[5] = {-0.5 * ls + ls * alpha, -ls * alpha, 0.5 * ls, 0.0, 0.0};
      c.uniaxial = approximate(grids.uniaxial, poly, poly2, f);
      c.volumetric = approximate(grids.volumetric, poly, poly2, h);
      break;
    }
  }
  return c;
}

SplinePreset parse_spline_preset(const std::string& name) {
  if (name == "corotated") return SplinePreset::corotated;
  if (name == "stvk") return SplinePreset::stvk;
  if (name == "neo_hookean") return SplinePreset::neo_hookean;
  throw std::invalid_argument("unknown spline preset '" + name +
                              "' (expected corotated, stvk or neo_hookean)");
}

}  // namespace tailor
