#pragma once
// The lower orders of Dual2<N> (forward/core/dual2.hpp) for the rod kinematics (private to
// forward/rods): Dual0, a plain value, and Dual1<N>, a value with its gradient in N inputs.
// The rod strains are written once (forward/rods/rod_kinematics.hpp) on a scalar type; a
// Hessian assembly runs them on Dual2<11>, a gradient request (the line search's first trial,
// the mixed block d2E/dxdp = ds/dx^T W_sq) on Dual1<11> and an energy request on Dual0, so
// each request pays only for the order it needs (Dual2<11> carries 1 + 11 + 121 numbers per
// operation, Dual1<11> 12, Dual0 one).
//
// Every operation computes its value, and Dual1 its gradient, with exactly the expressions
// Dual2 uses for its value and gradient (e.g. a / b as a * (1 / b), s a + c for the affine
// maps, f_a a.g + f_b b.g), so the three orders agree bit for bit on what they share: an
// energy, its gradient and its Hessian assembly see one function, and the line search compares
// energies computed by the same arithmetic (tests/forward/rods/rod_scalar_orders_test.cpp).
#include <Eigen/Core>
#include <cmath>

namespace tailor::rod_detail {

// A value with Dual2's value arithmetic.
struct Dual0 {
  double v = 0.0;
  Dual0() = default;
  Dual0(double value) : v(value) {}  // NOLINT: constants mix freely
  static Dual0 variable(double value, int) { return Dual0(value); }
  static Dual0 affine(const Dual0& a, double s, double c) { return Dual0(s * a.v + c); }

  friend Dual0 operator+(const Dual0& a, const Dual0& b) { return Dual0(a.v + b.v); }
  friend Dual0 operator-(const Dual0& a, const Dual0& b) { return Dual0(a.v - b.v); }
  friend Dual0 operator*(const Dual0& a, const Dual0& b) { return Dual0(a.v * b.v); }
  friend Dual0 operator/(const Dual0& a, const Dual0& b) { return Dual0(a.v * (1.0 / b.v)); }
  friend Dual0 operator-(const Dual0& a) { return affine(a, -1.0, 0.0); }
  friend Dual0 operator+(const Dual0& a, double c) { return affine(a, 1.0, c); }
  friend Dual0 operator+(double c, const Dual0& a) { return affine(a, 1.0, c); }
  friend Dual0 operator-(const Dual0& a, double c) { return affine(a, 1.0, -c); }
  friend Dual0 operator-(double c, const Dual0& a) { return affine(a, -1.0, c); }
  friend Dual0 operator*(const Dual0& a, double s) { return affine(a, s, 0.0); }
  friend Dual0 operator*(double s, const Dual0& a) { return affine(a, s, 0.0); }
  friend Dual0 operator/(const Dual0& a, double s) { return affine(a, 1.0 / s, 0.0); }
  friend Dual0 operator/(double c, const Dual0& b) { return c * reciprocal(b); }
  friend Dual0 reciprocal(const Dual0& a) { return Dual0(1.0 / a.v); }
  friend Dual0 sqrt(const Dual0& a) { return Dual0(std::sqrt(a.v)); }
  friend Dual0 sin(const Dual0& a) { return Dual0(std::sin(a.v)); }
  friend Dual0 cos(const Dual0& a) { return Dual0(std::cos(a.v)); }
  friend Dual0 atan2(const Dual0& y, const Dual0& x) { return Dual0(std::atan2(y.v, x.v)); }
};

// A value and its gradient in N inputs, with Dual2's value and gradient arithmetic.
template <int N>
struct Dual1 {
  using Gradient = Eigen::Matrix<double, N, 1>;
  double v = 0.0;
  Gradient g = Gradient::Zero();

  Dual1() = default;
  Dual1(double value) : v(value) {}  // NOLINT: constants mix freely
  static Dual1 variable(double value, int index) {
    Dual1 d(value);
    d.g[index] = 1.0;
    return d;
  }
  // f(a) given f and f' at a.v.
  static Dual1 unary(const Dual1& a, double f, double d1) {
    Dual1 r(Uninitialized{});
    r.v = f;
    for (int i = 0; i < N; ++i) r.g[i] = d1 * a.g[i];
    return r;
  }
  // f(a, b) given f and its first partial derivatives at (a.v, b.v).
  static Dual1 binary(const Dual1& a, const Dual1& b, double f, double fa, double fb) {
    Dual1 r(Uninitialized{});
    r.v = f;
    for (int i = 0; i < N; ++i) r.g[i] = fa * a.g[i] + fb * b.g[i];
    return r;
  }
  static Dual1 affine(const Dual1& a, double s, double c) {
    Dual1 r(Uninitialized{});
    r.v = s * a.v + c;
    for (int i = 0; i < N; ++i) r.g[i] = s * a.g[i];
    return r;
  }

  friend Dual1 operator+(const Dual1& a, const Dual1& b) { return binary(a, b, a.v + b.v, 1.0, 1.0); }
  friend Dual1 operator-(const Dual1& a, const Dual1& b) { return binary(a, b, a.v - b.v, 1.0, -1.0); }
  friend Dual1 operator*(const Dual1& a, const Dual1& b) { return binary(a, b, a.v * b.v, b.v, a.v); }
  friend Dual1 operator/(const Dual1& a, const Dual1& b) {
    const double inv = 1.0 / b.v, q = a.v * inv;
    return binary(a, b, q, inv, -q * inv);
  }
  friend Dual1 operator-(const Dual1& a) { return affine(a, -1.0, 0.0); }
  friend Dual1 operator+(const Dual1& a, double c) { return affine(a, 1.0, c); }
  friend Dual1 operator+(double c, const Dual1& a) { return affine(a, 1.0, c); }
  friend Dual1 operator-(const Dual1& a, double c) { return affine(a, 1.0, -c); }
  friend Dual1 operator-(double c, const Dual1& a) { return affine(a, -1.0, c); }
  friend Dual1 operator*(const Dual1& a, double s) { return affine(a, s, 0.0); }
  friend Dual1 operator*(double s, const Dual1& a) { return affine(a, s, 0.0); }
  friend Dual1 operator/(const Dual1& a, double s) { return affine(a, 1.0 / s, 0.0); }
  friend Dual1 operator/(double c, const Dual1& b) { return c * reciprocal(b); }

  friend Dual1 reciprocal(const Dual1& a) {
    const double inv = 1.0 / a.v;
    return unary(a, inv, -inv * inv);
  }
  friend Dual1 sqrt(const Dual1& a) {
    const double s = std::sqrt(a.v);
    return unary(a, s, 0.5 / s);
  }
  friend Dual1 sin(const Dual1& a) { return unary(a, std::sin(a.v), std::cos(a.v)); }
  friend Dual1 cos(const Dual1& a) { return unary(a, std::cos(a.v), -std::sin(a.v)); }
  friend Dual1 atan2(const Dual1& y, const Dual1& x) {
    const double r2 = x.v * x.v + y.v * y.v;
    return binary(y, x, std::atan2(y.v, x.v), x.v / r2, -y.v / r2);
  }

 private:
  struct Uninitialized {};
  explicit Dual1(Uninitialized) : g() {}
};

}  // namespace tailor::rod_detail
