#pragma once
// Three-vectors of Dual2 numbers (forward/core/dual2.hpp), with the few operations the rod
// kinematics needs (private to forward/rods): the discrete rod's strains are written once on
// these and give their exact gradients and Hessians in the stencil's N <= 11 variables.
#include <Eigen/Core>

#include "forward/core/dual2.hpp"

namespace tailor::rod_detail {

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
// a x b with `a` a Dual2Vec3<N> or a constant Eigen::Vector3d.
template <class Left, int N>
Dual2Vec3<N> cross(const Left& a, const Dual2Vec3<N>& b) {
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
