#pragma once
// Dual2<N>: a scalar carried with its exact gradient and Hessian with respect to N inputs
// (second-order forward-mode differentiation). A formula written once as a template on its
// scalar type runs on double for values and on Dual2 for exact first and second derivatives, with
// no finite differences and no hand-expanded terms that could miss a branch. The contact
// distances, barrier and mollifier (forward/contact), the torus distances (forward/tori), the
// rotation map (forward/rigid) and the rod stencils (forward/rods) are written this way.
//
// Every operation is one of three kernels (a function of one argument, of two arguments, or an
// affine map), written as plain loops: the chain rule to second order,
//   f(a):    g = f' a.g,               H = f' a.H + f'' a.g a.g^T
//   f(a, b): g = f_a a.g + f_b b.g,    H = f_a a.H + f_b b.H + f_aa a.g a.g^T + f_bb b.g b.g^T
//                                          + f_ab (a.g b.g^T + b.g a.g^T)
// so a translation unit instantiates three small loops per N instead of one Eigen expression per
// operation (the fixed-size expressions made these the slowest files of the build to compile).
// The operators are hidden friends: they take part in overload resolution only where a Dual2 is
// an operand. Tests: tests/forward/core/dual2_test.cpp (every operation against central
// differences, including atan2, sqrt and division near their edge cases).
#include <Eigen/Core>
#include <cmath>

namespace tailor {

template <int N>
struct Dual2 {
  static_assert(N > 0, "Dual2<N> needs at least one input");
  using Gradient = Eigen::Matrix<double, N, 1>;
  using Hessian = Eigen::Matrix<double, N, N>;
  double v = 0.0;
  Gradient g = Gradient::Zero();
  Hessian h = Hessian::Zero();

  Dual2() = default;
  Dual2(double value) : v(value) {}  // NOLINT: constants mix freely with Dual2 numbers
  // The input number `index` with value `value`.
  static Dual2 variable(double value, int index) {
    Dual2 d(value);
    d.g[index] = 1.0;
    return d;
  }

  // f(a) given f, f' and f'' at a.v.
  static Dual2 unary(const Dual2& a, double f, double d1, double d2) {
    Dual2 r(Uninitialized{});
    r.v = f;
    const double* ag = a.g.data();
    const double* ah = a.h.data();
    double* rg = r.g.data();
    double* rh = r.h.data();
    for (int i = 0; i < N; ++i) rg[i] = d1 * ag[i];
    for (int j = 0; j < N; ++j) {
      const double s = d2 * ag[j];
      for (int i = 0; i < N; ++i) rh[j * N + i] = d1 * ah[j * N + i] + s * ag[i];
    }
    return r;
  }

  // f(a, b) given f and its first and second partial derivatives at (a.v, b.v).
  static Dual2 binary(const Dual2& a, const Dual2& b, double f, double fa, double fb, double faa, double fab,
                      double fbb) {
    Dual2 r(Uninitialized{});
    r.v = f;
    const double* ag = a.g.data();
    const double* bg = b.g.data();
    const double* ah = a.h.data();
    const double* bh = b.h.data();
    double* rg = r.g.data();
    double* rh = r.h.data();
    for (int i = 0; i < N; ++i) rg[i] = fa * ag[i] + fb * bg[i];
    if (faa == 0.0 && fab == 0.0 && fbb == 0.0) {  // linear combinations
      for (int i = 0; i < N * N; ++i) rh[i] = fa * ah[i] + fb * bh[i];
      return r;
    }
    if (faa == 0.0 && fbb == 0.0) {  // products: no squared first-order terms
      for (int j = 0; j < N; ++j) {
        const double sa = fab * bg[j], sb = fab * ag[j];
        for (int i = 0; i < N; ++i)
          rh[j * N + i] = fa * ah[j * N + i] + fb * bh[j * N + i] + sa * ag[i] + sb * bg[i];
      }
      return r;
    }
    for (int j = 0; j < N; ++j) {
      const double sa = faa * ag[j] + fab * bg[j], sb = fab * ag[j] + fbb * bg[j];
      for (int i = 0; i < N; ++i)
        rh[j * N + i] = fa * ah[j * N + i] + fb * bh[j * N + i] + sa * ag[i] + sb * bg[i];
    }
    return r;
  }

  // s a + c.
  static Dual2 affine(const Dual2& a, double s, double c) {
    Dual2 r(Uninitialized{});
    r.v = s * a.v + c;
    const double* ag = a.g.data();
    const double* ah = a.h.data();
    double* rg = r.g.data();
    double* rh = r.h.data();
    for (int i = 0; i < N; ++i) rg[i] = s * ag[i];
    for (int i = 0; i < N * N; ++i) rh[i] = s * ah[i];
    return r;
  }

  friend Dual2 operator+(const Dual2& a, const Dual2& b) {
    return binary(a, b, a.v + b.v, 1.0, 1.0, 0.0, 0.0, 0.0);
  }
  friend Dual2 operator-(const Dual2& a, const Dual2& b) {
    return binary(a, b, a.v - b.v, 1.0, -1.0, 0.0, 0.0, 0.0);
  }
  friend Dual2 operator*(const Dual2& a, const Dual2& b) {
    return binary(a, b, a.v * b.v, b.v, a.v, 0.0, 1.0, 0.0);
  }
  // a / b: f_b = -a/b^2, f_ab = -1/b^2, f_bb = 2a/b^3.
  friend Dual2 operator/(const Dual2& a, const Dual2& b) {
    const double inv = 1.0 / b.v, q = a.v * inv;
    return binary(a, b, q, inv, -q * inv, 0.0, -inv * inv, 2.0 * q * inv * inv);
  }
  friend Dual2 operator-(const Dual2& a) { return affine(a, -1.0, 0.0); }

  friend Dual2 operator+(const Dual2& a, double c) { return affine(a, 1.0, c); }
  friend Dual2 operator+(double c, const Dual2& a) { return affine(a, 1.0, c); }
  friend Dual2 operator-(const Dual2& a, double c) { return affine(a, 1.0, -c); }
  friend Dual2 operator-(double c, const Dual2& a) { return affine(a, -1.0, c); }
  friend Dual2 operator*(const Dual2& a, double s) { return affine(a, s, 0.0); }
  friend Dual2 operator*(double s, const Dual2& a) { return affine(a, s, 0.0); }
  friend Dual2 operator/(const Dual2& a, double s) { return affine(a, 1.0 / s, 0.0); }
  friend Dual2 operator/(double c, const Dual2& b) { return c * reciprocal(b); }

  Dual2& operator+=(const Dual2& b) { return *this = *this + b; }
  Dual2& operator-=(const Dual2& b) { return *this = *this - b; }
  Dual2& operator*=(const Dual2& b) { return *this = *this * b; }
  Dual2& operator*=(double s) { return *this = *this * s; }

  friend Dual2 reciprocal(const Dual2& a) {
    const double inv = 1.0 / a.v;
    return unary(a, inv, -inv * inv, 2.0 * inv * inv * inv);
  }
  // f'' = -1 / (4 a^(3/2)); infinite at 0, where sqrt is not differentiable.
  friend Dual2 sqrt(const Dual2& a) {
    const double s = std::sqrt(a.v);
    return unary(a, s, 0.5 / s, -0.25 / (s * a.v));
  }
  friend Dual2 exp(const Dual2& a) {
    const double e = std::exp(a.v);
    return unary(a, e, e, e);
  }
  friend Dual2 log(const Dual2& a) {
    const double inv = 1.0 / a.v;
    return unary(a, std::log(a.v), inv, -inv * inv);
  }
  friend Dual2 sin(const Dual2& a) {
    const double s = std::sin(a.v), c = std::cos(a.v);
    return unary(a, s, c, -s);
  }
  friend Dual2 cos(const Dual2& a) {
    const double s = std::sin(a.v), c = std::cos(a.v);
    return unary(a, c, -s, -c);
  }
  // atan2(y, x), with r2 = x^2 + y^2: f_y = x / r2, f_x = -y / r2, f_xx = 2xy / r2^2 = -f_yy,
  // f_xy = (y^2 - x^2) / r2^2. Undefined at the origin, like its derivatives.
  friend Dual2 atan2(const Dual2& y, const Dual2& x) {
    const double r2 = x.v * x.v + y.v * y.v, r4 = r2 * r2;
    const double fxx = 2.0 * x.v * y.v / r4;
    return binary(y, x, std::atan2(y.v, x.v), x.v / r2, -y.v / r2, -fxx, (y.v * y.v - x.v * x.v) / r4, fxx);
  }

 private:
  struct Uninitialized {};
  // g and h left unset (Eigen's fixed-size default): every entry is written by the kernel.
  explicit Dual2(Uninitialized) : g(), h() {}
};

// f(a) given f, f' and f'' at a.v, for functions the type does not provide (the barrier, the
// mollifier).
template <int N>
Dual2<N> chain(const Dual2<N>& a, double f, double d1, double d2) {
  return Dual2<N>::unary(a, f, d1, d2);
}

// Plain doubles go through the same templates.
inline double reciprocal(double b) { return 1.0 / b; }

}  // namespace tailor
