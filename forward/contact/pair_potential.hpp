#pragma once
// The barrier potential of one contact pair (Li et al. 2020, eq. 8 per pair; the stiffness
// kappa is applied by the caller):
//   point-triangle (p, t0, t1, t2):  b(d^2(x); d_hat^2)
//   edge-edge (a0, a1, b0, b1):      m(c(x); eps) b(d^2(x); d_hat^2),  c = |(a1-a0) x (b1-b0)|^2
// with d^2 the classified squared distance (distance.hpp), b the barrier and m the mollifier
// (barrier.hpp). Derivatives are taken in the 12 stencil coordinates (point k, axis j -> 3k+j)
// by Dual2, so the mollified product's Hessian includes both cross terms m' b' (dc dd^T + dd dc^T).
#include <Eigen/Core>
#include <array>

#include "forward/contact/distance.hpp"

namespace tailor::contact {

enum class PairKind { point_triangle, edge_edge };

struct PairDerivatives {
  double value = 0.0;
  Eigen::Matrix<double, 12, 1> gradient = Eigen::Matrix<double, 12, 1>::Zero();
  Eigen::Matrix<double, 12, 12> hessian = Eigen::Matrix<double, 12, 12>::Zero();
  ClassifiedDistance distance;
  bool mollified = false;  // edge-edge with c < eps
};

// Value (and with `derivatives`, gradient and Hessian) of the pair's barrier at the stencil
// `points`; `s_hat` = d_hat^2, `mollifier_eps` the edge pair's threshold (ignored for
// point-triangle). Returns false, leaving `out` zero, when the pair is inactive (d >= d_hat).
bool pair_barrier(PairKind kind, const std::array<Point, 4>& points, double s_hat, double mollifier_eps,
                  bool derivatives, PairDerivatives& out);

// The classified squared distance of a pair (no derivatives).
ClassifiedDistance classify_pair(PairKind kind, const std::array<Point, 4>& points);

}  // namespace tailor::contact
