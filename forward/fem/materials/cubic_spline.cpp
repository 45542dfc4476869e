#include "forward/fem/materials/cubic_spline.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tailor {
namespace {

// Uniform cubic B-spline basis and its first two derivatives in u.
Eigen::Vector4d basis_value(double u) {
  const double v = 1.0 - u, u2 = u * u, u3 = u2 * u;
  return {v * v * v / 6.0, (3.0 * u3 - 6.0 * u2 + 4.0) / 6.0, (-3.0 * u3 + 3.0 * u2 + 3.0 * u + 1.0) / 6.0,
          u3 / 6.0};
}
Eigen::Vector4d basis_slope(double u) {
  const double v = 1.0 - u;
  return {-0.5 * v * v, 1.5 * u * u - 2.0 * u, -1.5 * u * u + u + 0.5, 0.5 * u * u};
}
Eigen::Vector4d basis_curvature(double u) { return {1.0 - u, 3.0 * u - 2.0, -3.0 * u + 1.0, u}; }

}  // namespace

CubicSpline::CubicSpline(double lower, double upper, int intervals, Eigen::VectorXd controls)
    : lower_(lower), upper_(upper), spacing_(0.0), intervals_(intervals), controls_(std::move(controls)) {
  if (!(std::isfinite(lower) && std::isfinite(upper) && lower < upper))
    throw std::invalid_argument("CubicSpline: the range must satisfy lower < upper, got [" +
                                std::to_string(lower) + ", " + std::to_string(upper) + "]");
  if (intervals < 1)
    throw std::invalid_argument("CubicSpline: at least one interval needed, got " +
                                std::to_string(intervals));
  spacing_ = (upper - lower) / intervals;
  set_controls(controls_);
}

CubicSpline CubicSpline::approximating(double lower, double upper, int intervals,
                                       const std::function<double(double)>& value,
                                       const std::function<double(double)>& second_derivative) {
  CubicSpline s(lower, upper, intervals, Eigen::VectorXd::Zero(intervals + 3));
  const double h = s.spacing();
  Eigen::VectorXd c(intervals + 3);
  for (int k = 0; k < intervals + 3; ++k) {
    const double t = lower + (k - 1) * h;
    c[k] = value(t) - h * h / 6.0 * second_derivative(t);
  }
  s.set_controls(c);
  return s;
}

void CubicSpline::set_controls(const Eigen::VectorXd& controls) {
  if (controls.size() != num_controls())
    throw std::invalid_argument("CubicSpline: expected " + std::to_string(num_controls()) +
                                " control values, got " + std::to_string(controls.size()));
  controls_ = controls;
}

int CubicSpline::interval(double x, double& u) const {
  const double t = (x - lower_) / spacing_;
  const int i =
      std::clamp(static_cast<int>(std::floor(std::clamp(t, 0.0, double(intervals_)))), 0, intervals_ - 1);
  u = t - i;
  return i;
}

CubicSpline::Basis CubicSpline::basis(double x) const {
  Basis b;
  if (x >= lower_ && x <= upper_) {
    double u = 0.0;
    b.first = interval(x, u);
    b.value = basis_value(u);
    b.slope = basis_slope(u) / spacing_;
    b.curvature = basis_curvature(u) / (spacing_ * spacing_);
    return b;
  }
  // Linear continuation from the nearest end.
  const bool below = x < lower_;
  const double end = below ? lower_ : upper_;
  const double u_end = below ? 0.0 : 1.0;
  b.first = below ? 0 : intervals_ - 1;
  b.slope = basis_slope(u_end) / spacing_;
  b.value = basis_value(u_end) + (x - end) * b.slope;
  b.curvature.setZero();
  return b;
}

CubicSpline::Sample CubicSpline::evaluate(double x) const {
  const Basis b = basis(x);
  const auto c = controls_.segment<4>(b.first);
  return {c.dot(b.value), c.dot(b.slope), c.dot(b.curvature)};
}

double CubicSpline::curvature_inside(int i, double u) const {
  return controls_.segment<4>(i).dot(basis_curvature(u)) / (spacing_ * spacing_);
}

double CubicSpline::slope_divided_difference(double a, double b) const {
  if (a < b) std::swap(a, b);
  // Integrate y'' piece by piece over [b, a] (midpoint rule, exact for linear pieces); pieces
  // are the intervals inside the range and the two linear continuations (y'' = 0).
  const double lo = std::max(b, lower_), hi = std::min(a, upper_);
  if (!(lo < hi)) {
    if (a == b && a >= lower_ && a <= upper_) return evaluate(a).curvature;
    return 0.0;  // both points in the same linear continuation (or touching it)
  }
  double ulo = 0.0, uhi = 0.0;
  const int ilo = interval(lo, ulo), ihi = interval(hi, uhi);
  if (ilo == ihi) {
    // Same piece: mean of a linear function is its midpoint value, times the covered fraction.
    const double mean = curvature_inside(ilo, 0.5 * (ulo + uhi));
    return a == b ? mean : mean * ((hi - lo) / (a - b));
  }
  double integral = curvature_inside(ilo, 0.5 * (ulo + 1.0)) * (1.0 - ulo) * spacing_;
  for (int i = ilo + 1; i < ihi; ++i) integral += curvature_inside(i, 0.5) * spacing_;
  integral += curvature_inside(ihi, 0.5 * uhi) * uhi * spacing_;
  return integral / (a - b);
}

}  // namespace tailor
