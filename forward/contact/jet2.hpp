#pragma once
// Jet2<N>: a scalar carried with its exact gradient and Hessian with respect to N inputs
// (second-order forward-mode differentiation by the chain and product rules). The contact
// distances, the barrier and the mollifier are written once as templates on the scalar and
// evaluated with Jet2 to get exact per-branch gradients and Hessians (no finite differences).
#include <Eigen/Core>
#include <cmath>

namespace tailor::contact {

template <int N>
struct Jet2 {
  using Gradient = Eigen::Matrix<double, N, 1>;
  using Hessian = Eigen::Matrix<double, N, N>;
  double v = 0.0;
  Gradient g = Gradient::Zero();
  Hessian h = Hessian::Zero();

  Jet2() = default;
  Jet2(double value) : v(value) {}  // NOLINT: constants mix freely with jets
  // The i-th input with value `value`.
  static Jet2 variable(double value, int i) {
    Jet2 j(value);
    j.g[i] = 1.0;
    return j;
  }
};

// f(a) given f, f', f'' at a.v: grad = f' a.g, Hess = f' a.h + f'' a.g a.g^T.
template <int N>
Jet2<N> chain(const Jet2<N>& a, double f, double df, double d2f) {
  Jet2<N> r;
  r.v = f;
  r.g = df * a.g;
  r.h = df * a.h + d2f * a.g * a.g.transpose();
  return r;
}

template <int N>
Jet2<N> operator+(const Jet2<N>& a, const Jet2<N>& b) {
  Jet2<N> r;
  r.v = a.v + b.v;
  r.g = a.g + b.g;
  r.h = a.h + b.h;
  return r;
}
template <int N>
Jet2<N> operator-(const Jet2<N>& a, const Jet2<N>& b) {
  Jet2<N> r;
  r.v = a.v - b.v;
  r.g = a.g - b.g;
  r.h = a.h - b.h;
  return r;
}
template <int N>
Jet2<N> operator-(const Jet2<N>& a) {
  Jet2<N> r;
  r.v = -a.v;
  r.g = -a.g;
  r.h = -a.h;
  return r;
}
template <int N>
Jet2<N> operator*(const Jet2<N>& a, const Jet2<N>& b) {
  Jet2<N> r;
  r.v = a.v * b.v;
  r.g = a.v * b.g + b.v * a.g;
  const Eigen::Matrix<double, N, N> outer = a.g * b.g.transpose();
  r.h = a.v * b.h + b.v * a.h + outer + outer.transpose();
  return r;
}
template <int N>
Jet2<N> operator*(double s, const Jet2<N>& a) {
  Jet2<N> r;
  r.v = s * a.v;
  r.g = s * a.g;
  r.h = s * a.h;
  return r;
}
// 1 / b by the chain rule, then a product.
template <int N>
Jet2<N> reciprocal(const Jet2<N>& b) {
  const double inv = 1.0 / b.v;
  return chain(b, inv, -inv * inv, 2.0 * inv * inv * inv);
}
template <int N>
Jet2<N> operator/(const Jet2<N>& a, const Jet2<N>& b) {
  return a * reciprocal(b);
}

// Plain doubles go through the same templates.
inline double reciprocal(double b) { return 1.0 / b; }

}  // namespace tailor::contact
