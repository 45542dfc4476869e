#pragma once
// Hessians of the bend-twist strains from cross-edge products (private to forward/rods; the
// Hessian path of the bending and twisting terms, docs/rods.md "Bench").
//
// With each edge's frame a function of that edge's own variables (its edge vector, and for the
// material frame its twist angle), every bend-twist strain is a function of a few dot products
// u . w of a vector u of edge i-1 and a vector w of edge i. For the right-handed orthonormal
// frames (t, a1, a2 = t x a1) and (t, m1, m2) (the material frame, a turned by theta about t),
// with D = |t0 + t1|^2 = 2 (1 + t0 . t1):
//   kb = 4 t0 x t1 / D,   (t0 x t1) . m2_0 = t1 . m1_0,  (t0 x t1) . m2_1 = -t0 . m1_1, ...
//   kappa_1 = kb . (m2_0 + m2_1) / 2 = 2 (t1 . m1_0 - t0 . m1_1) / D,
//   kappa_2 = -kb . (m1_0 + m1_1) / 2 = 2 (t1 . m2_0 - t0 . m2_1) / D,
// and the reference twist atan2(Y, X) of the transport u = P(t0 -> t1) a1_0 against a1_1
// (rod_kinematics.hpp, reference_twist_of), with c = t0 . t1 = D / 2 - 1:
//   X = u . a1_1 = c (a1_0 . a1_1) - (t0 . a1_1)(t1 . a1_0) - (t1 . a2_0)(t0 . a2_1) / (1 + c),
//   Y = -u . a2_1 = -(c (a1_0 . a2_1) - (t0 . a2_1)(t1 . a1_0) + (t1 . a2_0)(t0 . a1_1) / (1 + c))
// (the triple products expanded by (a x b) . (c x d) = (a . c)(b . d) - (a . d)(b . c) and
// t . a1 = t . a2 = 0). A dot product of a function of one edge's B variables with one of the
// other's has a block Hessian: [[sum w_k H(u_k), sum grad u_k grad w_k^T], [.., sum u_k H(w_k)]],
// formed here from the edges' own 3- or 4-variable derivatives (each edge's computed once and
// shared by its two stencils) instead of running the whole formula on 6- or 8-variable dual
// numbers. The strain, a function f of the K products, gives its Hessian by the chain rule,
//   d2f/dx2 = sum_k f_k d2p_k/dx2 + dp/dx^T f_pp dp/dx,
// with f's derivatives in the products from Dual2<K>. The identities hold for exactly
// orthonormal frames, so these Hessians equal the dual-number path's (which differentiates the
// formulas of rod_kinematics.hpp as written) to round-off: tests/forward/rods/
// rod_scalar_orders_test.cpp compares them stencil by stencil and term by term, and the
// derivative checks hold them against central differences. Values and gradients still come from
// the first-order path (bit-identical to every other path).
#include <Eigen/Core>
#include <array>

#include "forward/rods/rod_kinematics.hpp"

namespace tailor::rod_detail {

// A function of a stencil's two edges, each with B variables (block 0: edge i-1, block 1: edge
// i): value, gradient blocks and Hessian blocks (the block (1, 0) is h01^T).
template <int B>
struct CrossEdgeDual {
  double v = 0.0;
  Eigen::Matrix<double, B, 1> g0, g1;
  Eigen::Matrix<double, B, B> h00, h11, h01;
};

// u . w, u a function of block 0 and w of block 1.
template <int B>
CrossEdgeDual<B> cross_edge_dot(const Vec3Of<Dual2<B>>& u, const Vec3Of<Dual2<B>>& w) {
  CrossEdgeDual<B> r;
  r.v = u[0].v * w[0].v + u[1].v * w[1].v + u[2].v * w[2].v;
  r.g0 = w[0].v * u[0].g + w[1].v * u[1].g + w[2].v * u[2].g;
  r.g1 = u[0].v * w[0].g + u[1].v * w[1].g + u[2].v * w[2].g;
  r.h00 = w[0].v * u[0].h + w[1].v * u[1].h + w[2].v * u[2].h;
  r.h11 = u[0].v * w[0].h + u[1].v * w[1].h + u[2].v * w[2].h;
  r.h01 = u[0].g * w[0].g.transpose() + u[1].g * w[1].g.transpose() + u[2].g * w[2].g.transpose();
  return r;
}

// |u + w|^2, u a function of block 0 and w of block 1.
template <int B>
CrossEdgeDual<B> cross_edge_sum_squared(const Vec3Of<Dual2<B>>& u, const Vec3Of<Dual2<B>>& w) {
  CrossEdgeDual<B> r;
  const double s[3] = {u[0].v + w[0].v, u[1].v + w[1].v, u[2].v + w[2].v};
  r.v = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
  r.g0.setZero();
  r.g1.setZero();
  r.h00.setZero();
  r.h11.setZero();
  r.h01.setZero();
  for (int k = 0; k < 3; ++k) {
    r.g0 += (2.0 * s[k]) * u[k].g;
    r.g1 += (2.0 * s[k]) * w[k].g;
    r.h00 += 2.0 * (u[k].g * u[k].g.transpose() + s[k] * u[k].h);
    r.h11 += 2.0 * (w[k].g * w[k].g.transpose() + s[k] * w[k].h);
    r.h01 += 2.0 * (u[k].g * w[k].g.transpose());
  }
  return r;
}

// The Hessian of f(p_1 .. p_K) in the 2B variables (block 0, then block 1), from f's value,
// gradient and Hessian in the products (f on Dual2<K>, the products its variables 0 .. K-1).
template <int B, int K>
Eigen::Matrix<double, 2 * B, 2 * B> chained_hessian(const Dual2<K>& f,
                                                    const std::array<CrossEdgeDual<B>, K>& p) {
  Eigen::Matrix<double, K, 2 * B> G;
  Eigen::Matrix<double, B, B> h00 = Eigen::Matrix<double, B, B>::Zero(), h11 = h00, h01 = h00;
  for (int k = 0; k < K; ++k) {
    const CrossEdgeDual<B>& q = p[static_cast<std::size_t>(k)];
    G.row(k).template head<B>() = q.g0.transpose();
    G.row(k).template tail<B>() = q.g1.transpose();
    h00 += f.g[k] * q.h00;
    h11 += f.g[k] * q.h11;
    h01 += f.g[k] * q.h01;
  }
  Eigen::Matrix<double, 2 * B, 2 * B> H = G.transpose() * f.h * G;
  H.template topLeftCorner<B, B>() += h00;
  H.template bottomRightCorner<B, B>() += h11;
  H.template topRightCorner<B, B>() += h01;
  H.template bottomLeftCorner<B, B>() += h01.transpose();
  return H;
}

// Twisting: per edge its tangent and reference directors in its 3 edge coordinates.
struct ReferenceFrameVectors {
  Vec3Of<Dual2<3>> t, a1, a2;
};
inline ReferenceFrameVectors reference_frame_vectors(const EdgeFrameOf<Dual2<3>>& f) {
  return {f.t, f.a1, cross(f.t, f.a1)};
}

// Bending: per edge its tangent and material directors in (e_x, e_y, e_z, theta).
struct MaterialFrameVectors {
  Vec3Of<Dual2<4>> t, m1, m2;
};
inline MaterialFrameVectors material_frame_vectors(const EdgeFrameOf<Dual2<3>>& f, double theta) {
  auto embed = [](const Vec3Of<Dual2<3>>& a) {
    Vec3Of<Dual2<4>> r;
    for (int k = 0; k < 3; ++k) {
      r[k] = Dual2<4>(a[k].v);
      r[k].g.template head<3>() = a[k].g;
      r[k].h.template topLeftCorner<3, 3>() = a[k].h;
    }
    return r;
  };
  const Vec3Of<Dual2<4>> t = embed(f.t), a1 = embed(f.a1), a2 = embed(cross(f.t, f.a1));
  const Dual2<4> th = Dual2<4>::variable(theta, 3), c = cos(th), s = sin(th);
  return {t, c * a1 + s * a2, c * a2 - s * a1};
}

// Sum_a w_a d2kappa_a/dx2 in the 8 edge variables (e^{i-1} 0-2, e^i 3-5, theta^{i-1} 6,
// theta^i 7): kappa_1 = 2 (P1 - P2) / D, kappa_2 = 2 (P3 - P4) / D.
inline Eigen::Matrix<double, kEdgeVariables, kEdgeVariables> curvature_hessian_sum(
    const MaterialFrameVectors& f0, const MaterialFrameVectors& f1, const Eigen::Vector2d& w) {
  const std::array<CrossEdgeDual<4>, 5> p = {cross_edge_sum_squared(f0.t, f1.t), cross_edge_dot(f0.m1, f1.t),
                                             cross_edge_dot(f0.t, f1.m1), cross_edge_dot(f0.m2, f1.t),
                                             cross_edge_dot(f0.t, f1.m2)};
  using P = Dual2<5>;
  const P D = P::variable(p[0].v, 0), P1 = P::variable(p[1].v, 1), P2 = P::variable(p[2].v, 2),
          P3 = P::variable(p[3].v, 3), P4 = P::variable(p[4].v, 4);
  const P two_over_D = 2.0 * reciprocal(D);
  const P f = w[0] * (two_over_D * (P1 - P2)) + w[1] * (two_over_D * (P3 - P4));
  const Eigen::Matrix<double, 8, 8> blocks = chained_hessian<4, 5>(f, p);
  // Blocks (e^{i-1}, theta^{i-1}), (e^i, theta^i) -> edge variables.
  constexpr int to_edge[8] = {0, 1, 2, 6, 3, 4, 5, 7};
  Eigen::Matrix<double, kEdgeVariables, kEdgeVariables> H;
  for (int c = 0; c < 8; ++c)
    for (int r = 0; r < 8; ++r) H(to_edge[r], to_edge[c]) = blocks(r, c);
  return H;
}

// d2 m_ref / de2 in the 6 edge coordinates (e^{i-1} 0-2, e^i 3-5).
inline Eigen::Matrix<double, 6, 6> reference_twist_hessian(const ReferenceFrameVectors& f0,
                                                           const ReferenceFrameVectors& f1) {
  const std::array<CrossEdgeDual<3>, 7> p = {cross_edge_sum_squared(f0.t, f1.t), cross_edge_dot(f0.a1, f1.a1),
                                             cross_edge_dot(f0.a1, f1.a2),       cross_edge_dot(f0.t, f1.a1),
                                             cross_edge_dot(f0.t, f1.a2),        cross_edge_dot(f0.a1, f1.t),
                                             cross_edge_dot(f0.a2, f1.t)};
  using P = Dual2<7>;
  const P D = P::variable(p[0].v, 0), A11 = P::variable(p[1].v, 1), A12 = P::variable(p[2].v, 2),
          T0a1 = P::variable(p[3].v, 3), T0a2 = P::variable(p[4].v, 4), T1a1 = P::variable(p[5].v, 5),
          T1a2 = P::variable(p[6].v, 6);
  const P one_plus_c = 0.5 * D, c = one_plus_c - 1.0, inv = reciprocal(one_plus_c);
  const P X = c * A11 - T0a1 * T1a1 - (T1a2 * T0a2) * inv;
  const P Y = -(c * A12 - T0a2 * T1a1 + (T1a2 * T0a1) * inv);
  return chained_hessian<3, 7>(atan2(Y, X), p);
}

// The symmetric H_x = A^T H_e A of lift() for an 8 x 8 Hessian in the edge variables.
inline Eigen::Matrix<double, kBendTwistDofs, kBendTwistDofs> lift_hessian(
    const Eigen::Matrix<double, kEdgeVariables, kEdgeVariables>& h) {
  Eigen::Matrix<double, kBendTwistDofs, kEdgeVariables> half;
  for (int c = 0; c < kEdgeVariables; ++c) half.col(c) = lift_gradient(h.col(c));
  Eigen::Matrix<double, kBendTwistDofs, kBendTwistDofs> out;
  for (int row = 0; row < kBendTwistDofs; ++row)
    out.row(row) = lift_gradient(half.row(row).transpose()).transpose();
  return out;
}

}  // namespace tailor::rod_detail
