#pragma once
// Strains of the discrete elastic rod as dual numbers (private to forward/rods): edge length,
// material curvatures and twist of one stencil, with their exact gradients and Hessians in the
// stencil's DOFs, including the dependence of the time-parallel reference frame and of the
// reference twist on the positions (docs/rods.md, "Exact Hessian"). Written once on a scalar
// type T: Dual2<N> for value, gradient and Hessian, Dual1<N> for value and gradient, Dual0 for
// the value alone (forward/rods/low_order_duals.hpp; the three agree bit for bit on what they
// share).
#include <Eigen/Core>
#include <array>
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

// The same transport of a constant w from a constant u (a stored director from its stored
// tangent) to v: the same operations, with the constants kept as doubles (products with them
// are the scalar type's affine maps rather than products of two dual numbers, so the frames'
// derivatives cost about half; the values and derivatives are the same numbers).
template <class T>
Vec3Of<T> transport_stored(const Eigen::Vector3d& u, const Vec3Of<T>& v, const Eigen::Vector3d& w) {
  Vec3Of<T> sum, cw, bw;
  const Vec3Of<T> b = cross(u, v);
  for (int k = 0; k < 3; ++k) sum[k] = v[k] + u[k];
  const T c = dot(u, v);
  for (int k = 0; k < 3; ++k) cw[k] = c * w[k];
  bw[0] = b[1] * w[2] - b[2] * w[1];
  bw[1] = b[2] * w[0] - b[0] * w[2];
  bw[2] = b[0] * w[1] - b[1] * w[0];
  const T bdotw = b[0] * w[0] + b[1] * w[1] + b[2] * w[2];
  return cw + bw + (2.0 * bdotw / dot(sum, sum)) * b;
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

// The unit tangents and time-parallel reference directors of the stencil's two edges: the
// stored director transported to the current tangent.
template <class T>
struct EdgeFramesOf {
  Vec3Of<T> t0, t1, a10, a11;
};
// One edge's unit tangent and reference director, a function of its edge vector alone.
template <class T>
struct EdgeFrameOf {
  Vec3Of<T> t, a1;
};
template <class T>
EdgeFrameOf<T> edge_frame(const Vec3Of<T>& e, const Eigen::Vector3d& stored_tangent,
                          const Eigen::Vector3d& stored_director) {
  EdgeFrameOf<T> f;
  f.t = reciprocal(norm(e)) * e;
  f.a1 = transport_stored(stored_tangent, f.t, stored_director);
  return f;
}
template <class T>
EdgeFramesOf<T> edge_frames(const Vec3Of<T>& e0, const Vec3Of<T>& e1, const StoredFrames& stored) {
  const EdgeFrameOf<T> f0 = edge_frame(e0, stored.tangent0, stored.director0);
  const EdgeFrameOf<T> f1 = edge_frame(e1, stored.tangent1, stored.director1);
  return {f0.t, f1.t, f0.a1, f1.a1};
}

// The reference twist: the angle about t^i from the space-parallel transport of a1^{i-1} to
// a1^i, on the branch nearest the stored value.
template <class T>
T reference_twist_of(const EdgeFramesOf<T>& f, const StoredFrames& stored) {
  const Vec3Of<T> u = transport(f.t0, f.t1, f.a10);
  T raw = atan2(dot(cross(u, f.a11), f.t1), dot(u, f.a11));
  raw.v += nearest_branch_shift(raw.v, stored.reference_twist);
  return raw;
}

// (kb) = 2 t0 x t1 / (1 + t0 . t1) = 4 t0 x t1 / |t0 + t1|^2 (Bergou 2008 eq. 1; the second
// form keeps its relative precision when the edges nearly fold back onto each other).
template <class T>
Vec3Of<T> curvature_binormal(const EdgeFramesOf<T>& f) {
  const Vec3Of<T> tsum = f.t0 + f.t1;
  return (4.0 * reciprocal(dot(tsum, tsum))) * cross(f.t0, f.t1);
}

// kb projected on the reference frames of both edges: p_j = kb . a1^j, q_j = kb . a2^j
// (a2 = t x a1). They depend on the edges only; the twist angles enter below.
template <class T>
struct CurvatureProjections {
  T p0, q0, p1, q1;
};
template <class T>
CurvatureProjections<T> curvature_projections(const EdgeFramesOf<T>& f, const Vec3Of<T>& kb) {
  return {dot(kb, f.a10), dot(kb, cross(f.t0, f.a10)), dot(kb, f.a11), dot(kb, cross(f.t1, f.a11))};
}

// Material curvatures with the two edges' material frames averaged (Bergou 2010 section 4.1):
// m1 = c a1 + s a2, m2 = c a2 - s a1 (the reference frame turned by theta about t), so
//   kappa_1 = kb . (m2^{i-1} + m2^i) / 2 = ((c0 q0 - s0 p0) + (c1 q1 - s1 p1)) / 2,
//   kappa_2 = -kb . (m1^{i-1} + m1^i) / 2 = -((c0 p0 + s0 q0) + (c1 p1 + s1 q1)) / 2.
template <class T, class P>
void material_curvatures(const CurvatureProjections<P>& k, const T& theta0, const T& theta1, T& kappa1,
                         T& kappa2) {
  const T c0 = cos(theta0), s0 = sin(theta0), c1 = cos(theta1), s1 = sin(theta1);
  kappa1 = 0.5 * ((c0 * k.q0 - s0 * k.p0) + (c1 * k.q1 - s1 * k.p1));
  kappa2 = -0.5 * ((c0 * k.p0 + s0 * k.q0) + (c1 * k.p1 + s1 * k.q1));
}

// Bergou 2008 eq. (1) curvature binormal, the material curvatures of Bergou 2010 with the
// frames of both edges averaged, and the reference twist, from the two edge vectors and twist
// angles.
template <class T>
BendTwistStrainsOf<T> bend_twist_strains_of(const Vec3Of<T>& e0, const Vec3Of<T>& e1, const T& theta0,
                                            const T& theta1, const StoredFrames& stored) {
  const EdgeFramesOf<T> f = edge_frames(e0, e1, stored);
  const Vec3Of<T> kb = curvature_binormal(f);
  BendTwistStrainsOf<T> out;
  const CurvatureProjections<T> k = curvature_projections(f, kb);
  material_curvatures(k, theta0, theta1, out.kappa1, out.kappa2);
  out.reference_twist = reference_twist_of(f, stored);
  out.twist = theta1 - theta0 + out.reference_twist;
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

// Derivatives in 8 variables, the two edge vectors and twist angles (e^{i-1} 0-2, e^i 3-5,
// theta^{i-1} 6, theta^i 7; the strains depend on the positions only through the edges), are
// lifted to the stencil's 11 DOFs by the chain rule with the constant Jacobian A = de/dx.
inline constexpr int kEdgeVariables = 8;

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

// The material curvatures alone, as the bending term needs them: the projections p_j, q_j of
// kb depend on the two edges only and are differentiated in those 6 variables (T6 = Dual2<6>
// or Dual1<6>: 6x6 Hessians for the transports and kb, most of the work, instead of 11x11),
// then embedded in the 8 edge-and-twist variables (T8 = Dual2<8> or Dual1<8>) for the few
// operations with the twist angles, and lifted to the 11 DOFs. The edges' values are the same
// doubles (x_{i+1} - x_i) and the formulas the same, so the values are bend_twist_strains' bit
// for bit; the derivatives agree to round-off.
template <class T8, class T6>
T8 embed_edges(const T6& a) {
  T8 r(a.v);
  r.g.template head<6>() = a.g;
  if constexpr (requires { a.h; }) r.h.template topLeftCorner<6, 6>() = a.h;
  return r;
}

// An edge's frame differentiated in its own 3 coordinates (T3 = Dual2<3> or Dual1<3>):
// computed once per edge (forward/rods/rod_stencils.hpp, edge_frames_of_rod) and embedded into
// the 6 edge coordinates of each of the two stencils that share the edge, instead of being
// computed by both stencils in 6 variables (the norm and the transport, half of the work).
template <class T3>
EdgeFrameOf<T3> edge_frame_in_own_coordinates(const Eigen::Vector3d& e, const Eigen::Vector3d& stored_tangent,
                                              const Eigen::Vector3d& stored_director) {
  Vec3Of<T3> v;
  for (int k = 0; k < 3; ++k) v[k] = T3::variable(e[k], k);
  return edge_frame(v, stored_tangent, stored_director);
}
template <class T6, class T3>
T6 embed_edge(const T3& a, int offset) {
  T6 r(a.v);
  r.g.template segment<3>(offset) = a.g;
  if constexpr (requires { a.h; }) r.h.template block<3, 3>(offset, offset) = a.h;
  return r;
}
template <class T6, class T3>
Vec3Of<T6> embed_edge(const Vec3Of<T3>& a, int offset) {
  Vec3Of<T6> r;
  for (int k = 0; k < 3; ++k) r[k] = embed_edge<T6>(a[k], offset);
  return r;
}
// The stencil's frames in its 6 edge coordinates from its two edges' frames (edge i-1: 0-2).
template <class T6, class T3>
EdgeFramesOf<T6> stencil_frames(const EdgeFrameOf<T3>& f0, const EdgeFrameOf<T3>& f1) {
  return {embed_edge<T6>(f0.t, 0), embed_edge<T6>(f1.t, 3), embed_edge<T6>(f0.a1, 0), embed_edge<T6>(f1.a1, 3)};
}

template <class T6, class T8>
std::array<T8, 2> curvatures_from_frames(const EdgeFramesOf<T6>& f, const BendTwistLocal& local) {
  const CurvatureProjections<T6> k6 = curvature_projections(f, curvature_binormal(f));
  const CurvatureProjections<T8> k8{embed_edges<T8>(k6.p0), embed_edges<T8>(k6.q0), embed_edges<T8>(k6.p1),
                                    embed_edges<T8>(k6.q1)};
  std::array<T8, 2> kappa;
  material_curvatures(k8, T8::variable(local[9], 6), T8::variable(local[10], 7), kappa[0], kappa[1]);
  return kappa;
}

// The stencil's two edges (x_i - x_{i-1}, x_{i+1} - x_i), as doubles.
inline std::array<Eigen::Vector3d, 2> stencil_edges(const BendTwistLocal& local) {
  return {Eigen::Vector3d(local.segment<3>(3) - local.segment<3>(0)),
          Eigen::Vector3d(local.segment<3>(6) - local.segment<3>(3))};
}

template <class T3, class T6, class T8>
std::array<T8, 2> curvatures_by_edges(const BendTwistLocal& local, const StoredFrames& stored) {
  const auto e = stencil_edges(local);
  return curvatures_from_frames<T6, T8>(
      stencil_frames<T6>(edge_frame_in_own_coordinates<T3>(e[0], stored.tangent0, stored.director0),
                         edge_frame_in_own_coordinates<T3>(e[1], stored.tangent1, stored.director1)),
      local);
}

// The twist strain alone: m = theta^i - theta^{i-1} + m_ref is linear in the twist angles and
// m_ref depends on the two edges only (6 variables: no material frame, 6x6 Hessians), lifted
// to the 11 DOFs. Values bit-identical to bend_twist_strains' twist. T6 = Dual2<6> or Dual1<6>.
template <class T3, class T6>
T6 reference_twist_by_edges(const BendTwistLocal& local, const StoredFrames& stored) {
  const auto e = stencil_edges(local);
  return reference_twist_of(
      stencil_frames<T6>(edge_frame_in_own_coordinates<T3>(e[0], stored.tangent0, stored.director0),
                         edge_frame_in_own_coordinates<T3>(e[1], stored.tangent1, stored.director1)),
      stored);
}

inline Eigen::Matrix<double, kBendTwistDofs, 1> lift_edge_gradient(const Eigen::Matrix<double, 6, 1>& g) {
  Eigen::Matrix<double, kEdgeVariables, 1> padded;
  padded << g, 0.0, 0.0;
  return lift_gradient(padded);
}

inline BendTwistDual1 twist_from_reference(const Dual1<6>& raw, const BendTwistLocal& local) {
  BendTwistDual1 r((local[10] - local[9]) + raw.v);
  r.g = lift_edge_gradient(raw.g);
  r.g[9] = -1.0;
  r.g[10] = 1.0;
  return r;
}

inline BendTwistDual twist_from_reference(const Dual2<6>& raw, const BendTwistLocal& local) {
  BendTwistDual r((local[10] - local[9]) + raw.v);
  r.g = lift_edge_gradient(raw.g);
  r.g[9] = -1.0;
  r.g[10] = 1.0;
  Eigen::Matrix<double, kBendTwistDofs, 6> half;
  for (int c = 0; c < 6; ++c) half.col(c) = lift_edge_gradient(raw.h.col(c));
  for (int row = 0; row < kBendTwistDofs; ++row)
    r.h.row(row) = lift_edge_gradient(half.row(row).transpose()).transpose();
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
