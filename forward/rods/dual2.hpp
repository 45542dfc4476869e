#pragma once
// Second-order forward-mode dual numbers (private to forward/rods): a scalar together with
// its gradient and Hessian with respect to N independent variables. Arithmetic follows the
// chain rule to second order, so a formula written once in Dual2 gives the exact gradient and
// Hessian of the discrete rod's strains (no finite differences, no hand-expanded terms that
// could miss a branch). Used for the stencils of forward/rods (N <= 11 variables).
#include <Eigen/Core>
#include <cmath>

namespace tailor::rod_detail {

template <int N>
struct Dual2 {
  using Gradient = Eigen::Matrix<double, N, 1>;
  using Hessian = Eigen::Matrix<double, N, N>;
  double v = 0.0;
  Gradient g = Gradient::Zero();
  Hessian h = Hessian::Zero();

  Dual2() = default;
  Dual2(double value) : v(value) {}  // NOLINT: constants promote implicitly
  // The independent variable number `index` with value `value`.
  static Dual2 variable(double value, int index) {
    Dual2 d(value);
    d.g[index] = 1.0;
    return d;
  }
};

// f(a) with f' = d1 and f'' = d2 at a.v.
template <int N>
Dual2<N> chain(const Dual2<N>& a, double value, double d1, double d2) {
  Dual2<N> r;
  r.v = value;
  r.g = d1 * a.g;
  r.h = d1 * a.h + d2 * (a.g * a.g.transpose());
  return r;
}

template <int N>
Dual2<N> operator+(const Dual2<N>& a, const Dual2<N>& b) {
  Dual2<N> r;
  r.v = a.v + b.v;
  r.g = a.g + b.g;
  r.h = a.h + b.h;
  return r;
}
template <int N>
Dual2<N> operator-(const Dual2<N>& a, const Dual2<N>& b) {
  Dual2<N> r;
  r.v = a.v - b.v;
  r.g = a.g - b.g;
  r.h = a.h - b.h;
  return r;
}
template <int N>
Dual2<N> operator-(const Dual2<N>& a) {
  Dual2<N> r;
  r.v = -a.v;
  r.g = -a.g;
  r.h = -a.h;
  return r;
}
template <int N>
Dual2<N> operator*(const Dual2<N>& a, const Dual2<N>& b) {
  Dual2<N> r;
  r.v = a.v * b.v;
  r.g = a.v * b.g + b.v * a.g;
  const Eigen::Matrix<double, N, N> cross = a.g * b.g.transpose();
  r.h = a.v * b.h + b.v * a.h + cross + cross.transpose();
  return r;
}
template <int N>
Dual2<N> operator*(double s, const Dual2<N>& a) {
  Dual2<N> r;
  r.v = s * a.v;
  r.g = s * a.g;
  r.h = s * a.h;
  return r;
}
template <int N>
Dual2<N> operator*(const Dual2<N>& a, double s) {
  return s * a;
}
template <int N>
Dual2<N> operator+(const Dual2<N>& a, double s) {
  Dual2<N> r = a;
  r.v += s;
  return r;
}
template <int N>
Dual2<N> operator+(double s, const Dual2<N>& a) {
  return a + s;
}
template <int N>
Dual2<N> operator-(const Dual2<N>& a, double s) {
  return a + (-s);
}
template <int N>
Dual2<N> operator-(double s, const Dual2<N>& a) {
  return (-a) + s;
}
template <int N>
Dual2<N> reciprocal(const Dual2<N>& a) {
  const double inv = 1.0 / a.v;
  return chain(a, inv, -inv * inv, 2.0 * inv * inv * inv);
}
template <int N>
Dual2<N> operator/(const Dual2<N>& a, const Dual2<N>& b) {
  return a * reciprocal(b);
}
template <int N>
Dual2<N> operator/(const Dual2<N>& a, double s) {
  return (1.0 / s) * a;
}
template <int N>
Dual2<N> sqrt(const Dual2<N>& a) {
  const double s = std::sqrt(a.v);
  return chain(a, s, 0.5 / s, -0.25 / (s * a.v));
}
template <int N>
Dual2<N> sin(const Dual2<N>& a) {
  return chain(a, std::sin(a.v), std::cos(a.v), -std::sin(a.v));
}
template <int N>
Dual2<N> cos(const Dual2<N>& a) {
  return chain(a, std::cos(a.v), -std::sin(a.v), -std::cos(a.v));
}
// atan2(y, x) with partials f_y = x / r2, f_x = -y / r2 (r2 = x^2 + y^2).
template <int N>
Dual2<N> atan2(const Dual2<N>& y, const Dual2<N>& x) {
  const double r2 = x.v * x.v + y.v * y.v;
  const double fx = -y.v / r2, fy = x.v / r2;
  const double fxx = 2.0 * x.v * y.v / (r2 * r2), fyy = -fxx, fxy = (y.v * y.v - x.v * x.v) / (r2 * r2);
  Dual2<N> r;
  r.v = std::atan2(y.v, x.v);
  r.g = fx * x.g + fy * y.g;
  const Eigen::Matrix<double, N, N> cross = x.g * y.g.transpose();
  r.h = fx * x.h + fy * y.h + fxx * (x.g * x.g.transpose()) + fyy * (y.g * y.g.transpose()) +
        fxy * (cross + cross.transpose());
  return r;
}

// Three-vectors of dual numbers with the few operations the rod kinematics needs.
template <int N>
struct Dual2Vec3 {
  Dual2<N> c[3];
  Dual2<N>& operator[](int i) { return c[i]; }
  const Dual2<N>& operator[](int i) const { return c[i]; }
  static Dual2Vec3 constant(const Eigen::Vector3d& v) {
    Dual2Vec3 r;
    for (int i = 0; i < 3; ++i) r[i] = Dual2<N>(v[i]);
    return r;
  }
  Eigen::Vector3d value() const { return {c[0].v, c[1].v, c[2].v}; }
};

template <int N>
Dual2Vec3<N> operator+(const Dual2Vec3<N>& a, const Dual2Vec3<N>& b) {
  Dual2Vec3<N> r;
  for (int i = 0; i < 3; ++i) r[i] = a[i] + b[i];
  return r;
}
template <int N>
Dual2Vec3<N> operator-(const Dual2Vec3<N>& a, const Dual2Vec3<N>& b) {
  Dual2Vec3<N> r;
  for (int i = 0; i < 3; ++i) r[i] = a[i] - b[i];
  return r;
}
template <int N>
Dual2Vec3<N> operator*(const Dual2<N>& s, const Dual2Vec3<N>& a) {
  Dual2Vec3<N> r;
  for (int i = 0; i < 3; ++i) r[i] = s * a[i];
  return r;
}
template <int N>
Dual2Vec3<N> operator*(double s, const Dual2Vec3<N>& a) {
  Dual2Vec3<N> r;
  for (int i = 0; i < 3; ++i) r[i] = s * a[i];
  return r;
}
template <int N>
Dual2<N> dot(const Dual2Vec3<N>& a, const Dual2Vec3<N>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <int N>
Dual2<N> dot(const Eigen::Vector3d& a, const Dual2Vec3<N>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <int N>
Dual2Vec3<N> cross(const Dual2Vec3<N>& a, const Dual2Vec3<N>& b) {
  Dual2Vec3<N> r;
  r[0] = a[1] * b[2] - a[2] * b[1];
  r[1] = a[2] * b[0] - a[0] * b[2];
  r[2] = a[0] * b[1] - a[1] * b[0];
  return r;
}
template <int N>
Dual2Vec3<N> cross(const Eigen::Vector3d& a, const Dual2Vec3<N>& b) {
  Dual2Vec3<N> r;
  r[0] = a[1] * b[2] - a[2] * b[1];
  r[1] = a[2] * b[0] - a[0] * b[2];
  r[2] = a[0] * b[1] - a[1] * b[0];
  return r;
}
template <int N>
Dual2<N> norm(const Dual2Vec3<N>& a) {
  return sqrt(dot(a, a));
}

}  // namespace tailor::rod_detail
