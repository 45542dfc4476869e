#pragma once
// Three-vectors of dual numbers (Dual2<N>, forward/core/dual2.hpp, or its lower orders Dual1<N>
// and Dual0, forward/rods/low_order_duals.hpp), with the few operations the rod kinematics
// needs (private to forward/rods): the discrete rod's strains are written once on these and
// give their exact derivatives in the stencil's N <= 11 variables to the order asked for.
#include <Eigen/Core>

#include "forward/core/dual2.hpp"
#include "forward/rods/low_order_duals.hpp"

namespace tailor::rod_detail {

template <class T>
struct Vec3Of {
  T c[3];
  T& operator[](int i) { return c[i]; }
  const T& operator[](int i) const { return c[i]; }
  static Vec3Of constant(const Eigen::Vector3d& v) {
    Vec3Of r;
    for (int i = 0; i < 3; ++i) r[i] = T(v[i]);
    return r;
  }
  Eigen::Vector3d value() const { return {c[0].v, c[1].v, c[2].v}; }
};

template <int N>
using Dual2Vec3 = Vec3Of<Dual2<N>>;

template <class T>
Vec3Of<T> operator+(const Vec3Of<T>& a, const Vec3Of<T>& b) {
  Vec3Of<T> r;
  for (int i = 0; i < 3; ++i) r[i] = a[i] + b[i];
  return r;
}
template <class T>
Vec3Of<T> operator-(const Vec3Of<T>& a, const Vec3Of<T>& b) {
  Vec3Of<T> r;
  for (int i = 0; i < 3; ++i) r[i] = a[i] - b[i];
  return r;
}
template <class T>
Vec3Of<T> operator*(const T& s, const Vec3Of<T>& a) {
  Vec3Of<T> r;
  for (int i = 0; i < 3; ++i) r[i] = s * a[i];
  return r;
}
template <class T>
Vec3Of<T> operator*(double s, const Vec3Of<T>& a) {
  Vec3Of<T> r;
  for (int i = 0; i < 3; ++i) r[i] = s * a[i];
  return r;
}
template <class T>
T dot(const Vec3Of<T>& a, const Vec3Of<T>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <class T>
T dot(const Eigen::Vector3d& a, const Vec3Of<T>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
// a x b with `a` a Vec3Of<T> or a constant Eigen::Vector3d.
template <class Left, class T>
Vec3Of<T> cross(const Left& a, const Vec3Of<T>& b) {
  Vec3Of<T> r;
  r[0] = a[1] * b[2] - a[2] * b[1];
  r[1] = a[2] * b[0] - a[0] * b[2];
  r[2] = a[0] * b[1] - a[1] * b[0];
  return r;
}
template <class T>
T norm(const Vec3Of<T>& a) {
  return sqrt(dot(a, a));
}

}  // namespace tailor::rod_detail
