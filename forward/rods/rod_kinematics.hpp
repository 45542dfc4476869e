#pragma once
// Strains of the discrete elastic rod as dual numbers (private to forward/rods): edge length,
// material curvatures and twist of one stencil, with their exact gradients and Hessians in the
// stencil's DOFs, including the dependence of the time-parallel reference frame and of the
// reference twist on the positions (docs/rods.md, "Exact Hessian"). Written once on a scalar
// type T: Dual2<N> for value, gradient and Hessian, Dual1<N> for value and gradient, Dual0 for
// the value alone (forward/rods/low_order_duals.hpp; the three agree bit for bit on what they
// share).
#include <Eigen/Core>
#include <cmath>
#include <numbers>

#include "forward/rods/dual2_vec3.hpp"

namespace tailor::rod_detail {

// Local DOFs of a bend-twist stencil at interior vertex i:
//   0-2 x_{i-1}, 3-5 x_i, 6-8 x_{i+1}, 9 theta^{i-1}, 10 theta^i.
inline constexpr int kBendTwistDofs = 11;
using BendTwistDual = Dual2<kBendTwistDofs>;
using BendTwistDual1 = Dual1<kBendTwistDofs>;
using BendTwistLocal = Eigen::Matrix<double, kBendTwistDofs, 1>;

// Parallel transport of w from unit u to unit v: P w = c w + b x w + (b . w) / (1 + c) b with
// b = u x v, c = u . v (Rodrigues' rotation about b by the angle between u and v, written
// without dividing by |b| so it stays smooth at u = v; Bergou 2008 section 4.2). 1 + c is
// evaluated as |u + v|^2 / 2, which keeps its relative precision when u and v nearly fold back.
template <class T>
Vec3Of<T> transport(const Vec3Of<T>& u, const Vec3Of<T>& v, const Vec3Of<T>& w) {
  const Vec3Of<T> b = cross(u, v), sum = u + v;
  const T c = dot(u, v);
  return c * w + cross(b, w) + (2.0 * dot(b, w) / dot(sum, sum)) * b;
}

// The reference twist's branch: the value raw + 2 pi n nearest to `stored` [rad].
inline double nearest_branch_shift(double raw, double stored) {
  return 2.0 * std::numbers::pi * std::round((stored - raw) / (2.0 * std::numbers::pi));
}

// The stored frame data a stencil needs: per adjacent edge the last converged tangent and
// director, and the stored reference twist of the vertex.
struct StoredFrames {
  Eigen::Vector3d tangent0, director0, tangent1, director1;
  double reference_twist = 0.0;
};

template <class T>
struct BendTwistStrainsOf {
  T kappa1, kappa2;   // material curvatures (dimensionless: 2 tan(phi/2) scale)
  T twist;            // m_i = theta^i - theta^{i-1} + m_ref [rad]
  T reference_twist;  // m_ref, unwrapped
};
using BendTwistStrains = BendTwistStrainsOf<BendTwistDual>;

// Bergou 2008 eq. (1) curvature binormal, the material curvatures of Bergou 2010 with the
// frames of both edges averaged, and the reference twist (angle about t^i from the space-
// parallel transport of a1^{i-1} to a1^i), from the two edge vectors and twist angles.
template <class T>
BendTwistStrainsOf<T> bend_twist_strains_of(const Vec3Of<T>& e0, const Vec3Of<T>& e1, const T& theta0,
                                            const T& theta1, const StoredFrames& stored) {
  using D = T;
  using V = Vec3Of<T>;
  const D l0 = norm(e0), l1 = norm(e1);
  const V t0 = reciprocal(l0) * e0, t1 = reciprocal(l1) * e1;
  // (kb) = 2 t0 x t1 / (1 + t0 . t1) = 4 t0 x t1 / |t0 + t1|^2 (the second form keeps its
  // relative precision when the edges nearly fold back onto each other).
  const V tsum = t0 + t1;
  const V kb = (4.0 * reciprocal(dot(tsum, tsum))) * cross(t0, t1);

  // Time-parallel reference frames: stored director transported to the current tangent.
  const V a10 = transport(V::constant(stored.tangent0), t0, V::constant(stored.director0));
  const V a11 = transport(V::constant(stored.tangent1), t1, V::constant(stored.director1));
  const V a20 = cross(t0, a10), a21 = cross(t1, a11);
  // Material frames: reference frames rotated by theta about the tangent.
  const D c0 = cos(theta0), s0 = sin(theta0), c1 = cos(theta1), s1 = sin(theta1);
  const V m1_0 = c0 * a10 + s0 * a20, m2_0 = c0 * a20 - s0 * a10;
  const V m1_1 = c1 * a11 + s1 * a21, m2_1 = c1 * a21 - s1 * a11;

  BendTwistStrainsOf<T> out;
  out.kappa1 = 0.5 * dot(kb, m2_0 + m2_1);
  out.kappa2 = -0.5 * dot(kb, m1_0 + m1_1);

  const V u = transport(t0, t1, a10);
  D raw = atan2(dot(cross(u, a11), t1), dot(u, a11));
  raw.v += nearest_branch_shift(raw.v, stored.reference_twist);
  out.reference_twist = raw;
  out.twist = theta1 - theta0 + raw;
  return out;
}

// The strains with derivatives in the stencil's 11 DOFs directly.
// T = BendTwistDual (Hessians), BendTwistDual1 (gradients) or Dual0 (values).
template <class T = BendTwistDual>
BendTwistStrainsOf<T> bend_twist_strains(const BendTwistLocal& local, const StoredFrames& stored) {
  using V = Vec3Of<T>;
  auto var = [&](int index) { return T::variable(local[index], index); };
  V x0, x1, x2;
  for (int k = 0; k < 3; ++k) {
    x0[k] = var(k);
    x1[k] = var(3 + k);
    x2[k] = var(6 + k);
  }
  return bend_twist_strains_of<T>(x1 - x0, x2 - x1, var(9), var(10), stored);
}

// The same strains with derivatives in 8 variables, the two edge vectors and twist angles
// (e^{i-1} 0-2, e^i 3-5, theta^{i-1} 6, theta^i 7): the strains depend on the positions only
// through the edges, so a Dual2 operation carries an 8x8 Hessian instead of 11x11 (64 numbers
// instead of 121, half the work). lift() maps the derivatives to the 11 DOFs by the chain rule
// with the constant Jacobian de/dx. The edges' values are the same doubles (x_{i+1} - x_i), so
// the values are those of bend_twist_strains bit for bit; the derivatives agree to round-off.
// T = Dual2<8> or Dual1<8>.
inline constexpr int kEdgeVariables = 8;
template <class T>
BendTwistStrainsOf<T> bend_twist_strains_by_edges(const BendTwistLocal& local, const StoredFrames& stored) {
  Vec3Of<T> e0, e1;
  for (int k = 0; k < 3; ++k) {
    e0[k] = T::variable(local[3 + k] - local[k], k);
    e1[k] = T::variable(local[6 + k] - local[3 + k], 3 + k);
  }
  return bend_twist_strains_of<T>(e0, e1, T::variable(local[9], 6), T::variable(local[10], 7), stored);
}

// g_x = A^T g_e with A = de/dx (8 x 11): x_{i-1} -> -e^{i-1}, x_i -> e^{i-1} - e^i, x_{i+1} -> e^i.
inline Eigen::Matrix<double, kBendTwistDofs, 1> lift_gradient(const Eigen::Matrix<double, kEdgeVariables, 1>& g) {
  Eigen::Matrix<double, kBendTwistDofs, 1> out;
  for (int k = 0; k < 3; ++k) {
    out[k] = -g[k];
    out[3 + k] = g[k] - g[3 + k];
    out[6 + k] = g[3 + k];
  }
  out[9] = g[6];
  out[10] = g[7];
  return out;
}

inline BendTwistDual1 lift(const Dual1<kEdgeVariables>& a) {
  BendTwistDual1 r(a.v);
  r.g = lift_gradient(a.g);
  return r;
}

// H_x = A^T H_e A, as the gradient's map applied to the columns, then to the rows.
inline BendTwistDual lift(const Dual2<kEdgeVariables>& a) {
  BendTwistDual r(a.v);
  r.g = lift_gradient(a.g);
  Eigen::Matrix<double, kBendTwistDofs, kEdgeVariables> half;
  for (int c = 0; c < kEdgeVariables; ++c) half.col(c) = lift_gradient(a.h.col(c));
  for (int row = 0; row < kBendTwistDofs; ++row) r.h.row(row) = lift_gradient(half.row(row).transpose()).transpose();
  return r;
}

// Length of the edge between local DOFs 0-2 and 3-5, with its derivatives (T = Dual2<6>,
// Dual1<6> or Dual0).
template <class T = Dual2<6>>
T edge_length(const Eigen::Matrix<double, 6, 1>& local) {
  Vec3Of<T> e;
  for (int k = 0; k < 3; ++k) e[k] = T::variable(local[3 + k], 3 + k) - T::variable(local[k], k);
  return norm(e);
}

}  // namespace tailor::rod_detail
