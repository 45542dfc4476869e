#pragma once
// One-dimensional uniform cubic B-spline with linear extrapolation, the building block of the
// principal-stretch spline material (Xu, Sin, Zhu, Barbic 2015, "Nonlinear material design
// using principal stretches", ACM TOG 34(4)).
//
// Knots: x_i = lower + i h, i = 0..m, h = (upper - lower) / m (m = intervals >= 1).
// Control values: c_0 .. c_{m+2} (m + 3 of them), c_k the coefficient of the cubic B-spline
// centred at x_{k-1}. On [x_i, x_{i+1}], with u = (x - x_i)/h,
//   y(x) = c_i b0(u) + c_{i+1} b1(u) + c_{i+2} b2(u) + c_{i+3} b3(u),
//   b0 = (1-u)^3/6, b1 = (3u^3 - 6u^2 + 4)/6, b2 = (-3u^3 + 3u^2 + 3u + 1)/6, b3 = u^3/6.
// Outside [lower, upper] the curve continues linearly with the value and slope of the end.
//
// Why a B-spline and not an interpolating C2 or a C1 Hermite spline: it is C2 inside the range
// (Newton sees a continuous tangent), each point depends on 4 control values (cheap evaluation,
// sparse control derivatives), the curve is linear in the control values (exact, simple
// parameter derivatives), and it reproduces every cubic polynomial exactly with the
// quasi-interpolant c_k = p(t_k) - h^2/6 p''(t_k), t_k = lower + (k-1) h, so polynomial
// material presets of degree <= 3 are exact. At the range ends the curve is only C1 (the
// curvature drops to 0 in the linear continuation); presets keep the working range inside.
#include <Eigen/Core>
#include <functional>

namespace tailor {

class CubicSpline {
 public:
  // Throws std::invalid_argument unless lower < upper (finite), intervals >= 1 and
  // controls.size() == intervals + 3.
  CubicSpline(double lower, double upper, int intervals, Eigen::VectorXd controls);
  // The quasi-interpolant of a function given with its second derivative; exact for cubics.
  static CubicSpline approximating(double lower, double upper, int intervals,
                                   const std::function<double(double)>& value,
                                   const std::function<double(double)>& second_derivative);

  double lower() const { return lower_; }
  double upper() const { return upper_; }
  int intervals() const { return intervals_; }
  double spacing() const { return spacing_; }
  int num_controls() const { return intervals_ + 3; }
  const Eigen::VectorXd& controls() const { return controls_; }
  void set_controls(const Eigen::VectorXd& controls);  // throws on a size mismatch

  // Value, slope and curvature at x, each linear in the control values with weights over the
  // 4 controls first .. first + 3 (curvature weights are zero outside the range).
  struct Basis {
    int first = 0;
    Eigen::Vector4d value, slope, curvature;
  };
  Basis basis(double x) const;

  struct Sample {
    double value, slope, curvature;
  };
  Sample evaluate(double x) const;

  // (y'(a) - y'(b)) / (a - b), the mean curvature over [b, a], evaluated without cancellation
  // (y'' is piecewise linear, so the mean over each piece is y'' at its midpoint); y''(a) at a == b.
  double slope_divided_difference(double a, double b) const;

 private:
  // Interval index of x clamped to [0, m-1] and the local coordinate u (unclamped).
  int interval(double x, double& u) const;
  double curvature_inside(int i, double u) const;

  double lower_, upper_, spacing_;
  int intervals_;
  Eigen::VectorXd controls_;
};

}  // namespace tailor
