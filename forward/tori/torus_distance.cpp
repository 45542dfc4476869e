// Distance between two tori by a minimization over the core angles (see torus_distance.hpp).
#include "forward/tori/torus_distance.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "forward/core/dual2.hpp"
#include "forward/core/symmetric_eigen.hpp"
#include "forward/rigid/rotation.hpp"
#include "forward/tori/elliptic_distance.hpp"
#include "forward/tori/implicit_minimum.hpp"

namespace tailor::tori {
namespace {

using CoreJet = Dual2<16>;  // 0-1 core angles, 2-4 T_a, 5-7 w_a, 8-10 T_b, 11-13 w_b, 14 R_a, 15 R_b

// A core circle in the world: centre, in-plane axes (the first two columns of Q), radius.
struct Circle {
  Eigen::Vector3d centre, e1, e2;
  double radius;
  Eigen::Vector3d point(double t) const { return centre + radius * (std::cos(t) * e1 + std::sin(t) * e2); }
  Eigen::Vector3d tangent(double t) const { return radius * (-std::sin(t) * e1 + std::cos(t) * e2); }
};

Circle circle_of(const TorusPose& pose) {
  const Eigen::Matrix3d Q = rigid::rotation_matrix(pose.rotation);
  return {pose.position, Q.col(0), Q.col(1), pose.shape.major_radius};
}

// f = |c_a(t) - c_b(s)|^2 with its gradient and Hessian in (t, s).
double core_function(const Circle& a, const Circle& b, double t, double s, Eigen::Vector2d* g,
                     Eigen::Matrix2d* H) {
  const Eigen::Vector3d ca = a.point(t), cb = b.point(s), delta = ca - cb;
  if (g) {
    const Eigen::Vector3d ta = a.tangent(t), tb = b.tangent(s);
    const Eigen::Vector3d na = a.centre - ca, nb = b.centre - cb;  // second derivatives of the points
    (*g) << 2.0 * delta.dot(ta), -2.0 * delta.dot(tb);
    (*H) << 2.0 * (ta.dot(ta) + delta.dot(na)), -2.0 * ta.dot(tb), -2.0 * ta.dot(tb),
        2.0 * (tb.dot(tb) - delta.dot(nb));
  }
  return delta.squaredNorm();
}

// The angle of b nearest to point p (its projection onto b's plane).
double nearest_angle(const Circle& b, const Eigen::Vector3d& p) {
  const Eigen::Vector3d v = p - b.centre;
  const double x = v.dot(b.e1), y = v.dot(b.e2);
  return (x == 0.0 && y == 0.0) ? 0.0 : std::atan2(y, x);
}

// Newton with a backtracking line search from (t, s); returns f at the end. A decrease of f
// resolves the minimizer only to ~sqrt(eps) in the angles (f is flat there), and the
// derivatives f_y at the minimizer are first order in that error: so the end polishes the
// angles by plain Newton steps on f_u = 0 while they shrink |f_u| (quadratic convergence).
double polish(const Circle& a, const Circle& b, double& t, double& s, int max_iterations) {
  Eigen::Vector2d g;
  Eigen::Matrix2d H;
  double f = core_function(a, b, t, s, &g, &H);
  for (int it = 0; it < max_iterations; ++it) {
    Eigen::Vector2d lambda;
    Eigen::Matrix2d vectors;
    symmetric_eigen(H, lambda, vectors);
    const double scale = std::max(1e-300, lambda.cwiseAbs().maxCoeff());
    // Eigenvalues floored to a positive fraction of the largest (a descent direction).
    Eigen::Vector2d floored = lambda;
    for (int k = 0; k < 2; ++k)
      if (lambda[k] < 1e-8 * scale) floored[k] = std::max(std::abs(lambda[k]), 1e-3 * scale);
    const Eigen::Vector2d step = -vectors * (vectors.transpose() * g).cwiseQuotient(floored);
    if (!(step.norm() > 1e-15)) break;
    double alpha = 1.0, f_new = f;
    double tn = t, sn = s;
    bool decreased = false;
    for (int ls = 0; ls < 40; ++ls) {
      tn = t + alpha * step[0];
      sn = s + alpha * step[1];
      f_new = core_function(a, b, tn, sn, nullptr, nullptr);
      if (f_new <= f + 1e-4 * alpha * g.dot(step)) {
        decreased = true;
        break;
      }
      alpha *= 0.5;
    }
    if (!decreased) break;  // f resolved to round-off: the gradient polish below
    const bool tiny = alpha * step.norm() < 1e-14;
    t = tn;
    s = sn;
    f = core_function(a, b, t, s, &g, &H);
    if (tiny) break;
  }
  for (int it = 0; it < 8; ++it) {
    if (!(H.determinant() > 0.0 && H(0, 0) > 0.0)) break;
    const Eigen::Vector2d step = -H.ldlt().solve(g);
    Eigen::Vector2d gn;
    Eigen::Matrix2d Hn;
    const double fn = core_function(a, b, t + step[0], s + step[1], &gn, &Hn);
    if (!(gn.norm() < g.norm())) break;
    t += step[0];
    s += step[1];
    f = fn;
    g = gn;
    H = Hn;
  }
  return f;
}

// The Dual2 of one core point's coordinates in the 16 jet variables.
std::array<CoreJet, 3> core_point_jet(const TorusPose& pose, double angle, int angle_slot, int t_slot,
                                      int w_slot, int radius_slot) {
  const rigid::RotationDerivatives D = rigid::rotation_derivatives(pose.rotation);
  CoreJet c = CoreJet(std::cos(angle)), s = CoreJet(std::sin(angle));
  c.g[angle_slot] = -std::sin(angle);
  c.h(angle_slot, angle_slot) = -std::cos(angle);
  s.g[angle_slot] = std::cos(angle);
  s.h(angle_slot, angle_slot) = -std::sin(angle);
  const CoreJet radius = CoreJet::variable(pose.shape.major_radius, radius_slot);
  std::array<CoreJet, 3> out;
  for (int j = 0; j < 3; ++j) {
    std::array<CoreJet, 2> q;
    for (int k = 0; k < 2; ++k) {
      q[k] = CoreJet(D.rotation(j, k));
      for (int l = 0; l < 3; ++l) {
        q[k].g[w_slot + l] = D.first[l](j, k);
        for (int m = 0; m < 3; ++m) q[k].h(w_slot + l, w_slot + m) = D.second[l][m](j, k);
      }
    }
    out[j] = CoreJet::variable(pose.position[j], t_slot + j) + radius * (q[0] * c + q[1] * s);
  }
  return out;
}

}  // namespace

Eigen::Vector3d core_point(const TorusPose& pose, double theta) { return circle_of(pose).point(theta); }

TorusDistance torus_distance(const TorusPose& a, const TorusPose& b, bool derivatives,
                             const DistanceOptions& options) {
  if (is_elliptic(a.shape) || is_elliptic(b.shape))
    return elliptic_torus_distance(a, b, derivatives, options);
  const Circle ca = circle_of(a), cb = circle_of(b);
  const int n = std::max(4, options.samples);
  // Samples of f(t, s(t)), s(t) the nearest angle of b.
  std::vector<double> value(static_cast<std::size_t>(n)), angle_b(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const double t = 2.0 * M_PI * k / n;
    const Eigen::Vector3d p = ca.point(t);
    angle_b[static_cast<std::size_t>(k)] = nearest_angle(cb, p);
    value[static_cast<std::size_t>(k)] = (p - cb.point(angle_b[static_cast<std::size_t>(k)])).squaredNorm();
  }
  std::vector<int> minima;
  for (int k = 0; k < n; ++k) {
    const double v = value[static_cast<std::size_t>(k)];
    if (v <= value[static_cast<std::size_t>((k + n - 1) % n)] &&
        v <= value[static_cast<std::size_t>((k + 1) % n)])
      minima.push_back(k);
  }
  std::sort(minima.begin(), minima.end(), [&](int i, int j) {
    return value[static_cast<std::size_t>(i)] < value[static_cast<std::size_t>(j)];
  });
  if (minima.empty()) minima.push_back(0);  // a constant sequence (coaxial circles)
  if (static_cast<int>(minima.size()) > options.max_starts)
    minima.resize(static_cast<std::size_t>(options.max_starts));
  TorusDistance out;
  double best = std::numeric_limits<double>::infinity();
  for (int k : minima) {
    double t = 2.0 * M_PI * k / n, s = angle_b[static_cast<std::size_t>(k)];
    const double f = polish(ca, cb, t, s, options.max_iterations);
    if (f < best) {
      best = f;
      out.theta_a = t;
      out.theta_b = s;
    }
  }
  out.core_distance = std::sqrt(best);
  out.distance = out.core_distance - a.shape.minor_radius - b.shape.minor_radius;

  Eigen::Vector2d g;
  Eigen::Matrix2d H;
  core_function(ca, cb, out.theta_a, out.theta_b, &g, &H);
  const Eigen::Vector2d lambda = symmetric_eigenvalues(H);
  out.degenerate = !(lambda[0] > 1e-9 * std::max(lambda.cwiseAbs().maxCoeff(),
                                                 a.shape.major_radius * b.shape.major_radius)) ||
                   !(out.core_distance > 0.0);
  if (!derivatives || out.degenerate) return out;

  const std::array<CoreJet, 3> pa = core_point_jet(a, out.theta_a, 0, 2, 5, 14);
  const std::array<CoreJet, 3> pb = core_point_jet(b, out.theta_b, 1, 8, 11, 15);
  CoreJet f = CoreJet(0.0);
  for (int j = 0; j < 3; ++j) {
    const CoreJet delta = pa[j] - pb[j];
    f = f + delta * delta;
  }
  // Implicit function theorem on f_u = 0: D^2's gradient f_y and Hessian f_yy - f_yu f_uu^-1 f_uy.
  Eigen::Matrix<double, 14, 1> gD;
  Eigen::Matrix<double, 14, 14> HD;
  sqrt_minimum_derivatives<2, 14>(f, out.core_distance, options.implicit_correction, gD, HD);
  // Jet variables 2..15 -> pair variables: 0..11 the DOFs, then R_a -> 12, R_b -> 14.
  const int map[14] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 14};
  for (int i = 0; i < 14; ++i) {
    out.gradient[map[i]] = gD[i];
    for (int j = 0; j < 14; ++j) out.hessian(map[i], map[j]) = HD(i, j);
  }
  out.gradient[13] = -1.0;
  out.gradient[15] = -1.0;
  return out;
}

}  // namespace tailor::tori
