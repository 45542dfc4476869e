// Distance between tori with elliptic tubes by a surface-surface minimization (see
// elliptic_distance.hpp).
#include "forward/tori/elliptic_distance.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "forward/core/dual2.hpp"
#include "forward/core/symmetric_eigen.hpp"
#include "forward/rigid/rotation.hpp"
#include "forward/tori/implicit_minimum.hpp"

namespace tailor::tori {
namespace {

// 0-3 (u_a, v_a, u_b, v_b), 4-6 T_a, 7-9 w_a, 10-12 T_b, 13-15 w_b, 16-18 (R_a, r_a, r1_a),
// 19-21 (R_b, r_b, r1_b).
using PairJet = Dual2<22>;
using Vector4 = Eigen::Vector4d;
using Matrix4 = Eigen::Matrix4d;

// A torus surface in the world: its frame and semi-axes.
struct Surface {
  Eigen::Vector3d T;
  Eigen::Matrix3d Q;
  double R, r, r1;
};

Surface surface_of(const TorusPose& pose) {
  return {pose.position, rigid::rotation_matrix(pose.rotation), pose.shape.major_radius,
          pose.shape.minor_radius, axial_radius(pose.shape)};
}

Eigen::Vector3d point_of(const Surface& s, double u, double v) {
  const double rho = s.R + s.r * std::cos(v);
  return s.T + s.Q * Eigen::Vector3d(rho * std::cos(u), rho * std::sin(u), s.r1 * std::sin(v));
}

// The world point with its first and second derivatives in (u, v).
struct SurfaceJet {
  Eigen::Vector3d x, xu, xv, xuu, xuv, xvv;
};

SurfaceJet surface_jet(const Surface& s, double u, double v) {
  const double cu = std::cos(u), su = std::sin(u), cv = std::cos(v), sv = std::sin(v);
  const double rho = s.R + s.r * cv;
  SurfaceJet j;
  j.x = s.T + s.Q * Eigen::Vector3d(rho * cu, rho * su, s.r1 * sv);
  j.xu = s.Q * Eigen::Vector3d(-rho * su, rho * cu, 0.0);
  j.xv = s.Q * Eigen::Vector3d(-s.r * sv * cu, -s.r * sv * su, s.r1 * cv);
  j.xuu = s.Q * Eigen::Vector3d(-rho * cu, -rho * su, 0.0);
  j.xuv = s.Q * Eigen::Vector3d(s.r * sv * su, -s.r * sv * cu, 0.0);
  j.xvv = s.Q * Eigen::Vector3d(-s.r * cv * cu, -s.r * cv * su, -s.r1 * sv);
  return j;
}

// f = |S_a - S_b|^2 with its gradient and Hessian in u = (u_a, v_a, u_b, v_b).
double pair_function(const Surface& a, const Surface& b, const Vector4& u, Vector4* g, Matrix4* H) {
  if (!g) return (point_of(a, u[0], u[1]) - point_of(b, u[2], u[3])).squaredNorm();
  const SurfaceJet ja = surface_jet(a, u[0], u[1]), jb = surface_jet(b, u[2], u[3]);
  const Eigen::Vector3d delta = ja.x - jb.x;
  Eigen::Matrix<double, 3, 4> D;
  D << ja.xu, ja.xv, -jb.xu, -jb.xv;
  *g = 2.0 * D.transpose() * delta;
  *H = 2.0 * D.transpose() * D;
  (*H)(0, 0) += 2.0 * delta.dot(ja.xuu);
  (*H)(0, 1) += 2.0 * delta.dot(ja.xuv);
  (*H)(1, 0) += 2.0 * delta.dot(ja.xuv);
  (*H)(1, 1) += 2.0 * delta.dot(ja.xvv);
  (*H)(2, 2) -= 2.0 * delta.dot(jb.xuu);
  (*H)(2, 3) -= 2.0 * delta.dot(jb.xuv);
  (*H)(3, 2) -= 2.0 * delta.dot(jb.xuv);
  (*H)(3, 3) -= 2.0 * delta.dot(jb.xvv);
  return delta.squaredNorm();
}

// g of solid `s` at world point x, with its gradient and Hessian in x when asked.
double implicit_of(const Surface& s, const Eigen::Vector3d& x, Eigen::Vector3d* grad, Eigen::Matrix3d* hess) {
  const Eigen::Vector3d y = s.Q.transpose() * (x - s.T);
  const double horizontal = std::max(std::hypot(y[0], y[1]), 1e-300), rho = horizontal - s.R;
  const double value = rho * rho / (s.r * s.r) + y[2] * y[2] / (s.r1 * s.r1) - 1.0;
  if (grad) {
    const Eigen::Vector3d n(y[0] / horizontal, y[1] / horizontal, 0.0);
    const Eigen::Vector3d gy =
        2.0 * rho / (s.r * s.r) * n + Eigen::Vector3d(0, 0, 2.0 * y[2] / (s.r1 * s.r1));
    Eigen::Matrix3d planar = Eigen::Matrix3d::Zero();
    planar.topLeftCorner<2, 2>() = Eigen::Matrix2d::Identity();
    Eigen::Matrix3d hy = 2.0 / (s.r * s.r) * n * n.transpose() +
                         2.0 * rho / (s.r * s.r * horizontal) * (planar - n * n.transpose());
    hy(2, 2) = 2.0 / (s.r1 * s.r1);
    *grad = s.Q * gy;
    *hess = s.Q * hy * s.Q.transpose();
  }
  return value;
}

// h(u, v) = g_solid(S_surface(u, v)) with its gradient and Hessian in (u, v).
double implicit_on_surface(const Surface& surface, const Surface& solid, const Eigen::Vector2d& u,
                           Eigen::Vector2d* g, Eigen::Matrix2d* H) {
  if (!g) return implicit_of(solid, point_of(surface, u[0], u[1]), nullptr, nullptr);
  const SurfaceJet j = surface_jet(surface, u[0], u[1]);
  Eigen::Vector3d gx;
  Eigen::Matrix3d hx;
  const double value = implicit_of(solid, j.x, &gx, &hx);
  Eigen::Matrix<double, 3, 2> D;
  D << j.xu, j.xv;
  *g = D.transpose() * gx;
  *H = D.transpose() * hx * D;
  (*H)(0, 0) += gx.dot(j.xuu);
  (*H)(0, 1) += gx.dot(j.xuv);
  (*H)(1, 0) += gx.dot(j.xuv);
  (*H)(1, 1) += gx.dot(j.xvv);
  return value;
}

// Newton with floored eigenvalues and a backtracking line search on `function` (value, and
// gradient and Hessian when given pointers), then plain Newton steps while they shrink the
// gradient (quadratic convergence to the stationary point, past what a decrease of f resolves).
// A stationary point with negative curvature (a saddle: symmetric poses stop there with a zero
// gradient) is left along the most negative eigenvector, whichever sign decreases f, and Newton
// runs again.
template <int N, class Function>
double newton_minimize(const Function& function, Eigen::Matrix<double, N, 1>& x, int max_iterations) {
  using VectorN = Eigen::Matrix<double, N, 1>;
  using MatrixN = Eigen::Matrix<double, N, N>;
  VectorN g;
  MatrixN H;
  double f = function(x, &g, &H);
  for (int escape = 0;; ++escape) {
    for (int it = 0; it < max_iterations; ++it) {
      VectorN lambda;
      MatrixN vectors;
      symmetric_eigen(H, lambda, vectors);
      const double scale = std::max(1e-300, lambda.cwiseAbs().maxCoeff());
      VectorN floored = lambda;
      for (int k = 0; k < N; ++k)
        if (lambda[k] < 1e-8 * scale) floored[k] = std::max(std::abs(lambda[k]), 1e-3 * scale);
      const VectorN step = -vectors * (vectors.transpose() * g).cwiseQuotient(floored);
      if (!(step.norm() > 1e-15)) break;
      double alpha = 1.0;
      VectorN trial = x;
      bool decreased = false;
      for (int ls = 0; ls < 40; ++ls) {
        trial = x + alpha * step;
        if (function(trial, nullptr, nullptr) <= f + 1e-4 * alpha * g.dot(step)) {
          decreased = true;
          break;
        }
        alpha *= 0.5;
      }
      if (!decreased) break;
      const bool tiny = alpha * step.norm() < 1e-14;
      x = trial;
      f = function(x, &g, &H);
      if (tiny) break;
    }
    for (int it = 0; it < 8; ++it) {
      Eigen::LDLT<MatrixN> ldlt(H);
      if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) break;
      const VectorN step = -ldlt.solve(g);
      VectorN gn;
      MatrixN Hn;
      const double fn = function(VectorN(x + step), &gn, &Hn);
      if (!(gn.norm() < g.norm())) break;
      x += step;
      f = fn;
      g = gn;
      H = Hn;
    }
    VectorN lambda;
    MatrixN vectors;
    symmetric_eigen(H, lambda, vectors);
    const double scale = std::max(1e-300, lambda.cwiseAbs().maxCoeff());
    if (escape >= 4 || !(lambda[0] < -1e-9 * scale)) return f;
    // The quadratic model drops by |lambda| t^2 / 2 along the eigenvector: from t = sqrt(f / |lambda|)
    // (the model's decrease comparable to f) halving until f decreases.
    const VectorN e = vectors.col(0);
    bool moved = false;
    for (double t = std::sqrt(std::max(f, 1e-30) / -lambda[0]); t > 1e-12 && !moved; t *= 0.5)
      for (double sign : {1.0, -1.0}) {
        const VectorN trial = x + sign * t * e;
        if (function(trial, nullptr, nullptr) < f) {
          x = trial;
          moved = true;
          break;
        }
      }
    if (!moved) return f;
    f = function(x, &g, &H);
  }
}

// The smallest of g_solid over `surface`: Newton from each start (u, v).
double smallest_implicit(const Surface& surface, const Surface& solid,
                         const std::vector<Eigen::Vector2d>& starts, int max_iterations) {
  double best = std::numeric_limits<double>::infinity();
  auto h = [&](const Eigen::Vector2d& u, Eigen::Vector2d* g, Eigen::Matrix2d* H) {
    return implicit_on_surface(surface, solid, u, g, H);
  };
  for (Eigen::Vector2d u : starts) best = std::min(best, newton_minimize<2>(h, u, max_iterations));
  return best;
}

// The Dual2 of a surface point's coordinates; slots: (u, v) at angle_slot, T, w, and (R, r, r1)
// at radius_slot (r1 on r's slot for a circular tube).
std::array<PairJet, 3> surface_point_jet(const TorusPose& pose, double u, double v, int angle_slot,
                                         int t_slot, int w_slot, int radius_slot) {
  const rigid::RotationDerivatives D = rigid::rotation_derivatives(pose.rotation);
  auto trig = [](double angle, int slot, PairJet& c, PairJet& s) {
    c = PairJet(std::cos(angle));
    s = PairJet(std::sin(angle));
    c.g[slot] = -std::sin(angle);
    c.h(slot, slot) = -std::cos(angle);
    s.g[slot] = std::cos(angle);
    s.h(slot, slot) = -std::sin(angle);
  };
  PairJet cu, su, cv, sv;
  trig(u, angle_slot, cu, su);
  trig(v, angle_slot + 1, cv, sv);
  const PairJet R = PairJet::variable(pose.shape.major_radius, radius_slot);
  const PairJet r = PairJet::variable(pose.shape.minor_radius, radius_slot + 1);
  const PairJet r1 = PairJet::variable(axial_radius(pose.shape),
                                       is_elliptic(pose.shape) ? radius_slot + 2 : radius_slot + 1);
  const PairJet rho = R + r * cv;
  const std::array<PairJet, 3> body = {rho * cu, rho * su, r1 * sv};
  std::array<PairJet, 3> out;
  for (int j = 0; j < 3; ++j) {
    out[j] = PairJet::variable(pose.position[j], t_slot + j);
    for (int k = 0; k < 3; ++k) {
      PairJet q(D.rotation(j, k));
      for (int l = 0; l < 3; ++l) {
        q.g[w_slot + l] = D.first[l](j, k);
        for (int m = 0; m < 3; ++m) q.h(w_slot + l, w_slot + m) = D.second[l][m](j, k);
      }
      out[j] = out[j] + q * body[k];
    }
  }
  return out;
}

}  // namespace

Eigen::Vector3d surface_point(const TorusPose& pose, double u, double v) {
  return point_of(surface_of(pose), u, v);
}

double implicit_value(const TorusPose& pose, const Eigen::Vector3d& x) {
  return implicit_of(surface_of(pose), x, nullptr, nullptr);
}

TorusDistance elliptic_torus_distance(const TorusPose& a, const TorusPose& b, bool derivatives,
                                      const DistanceOptions& options) {
  if (!a.position.allFinite() || !a.rotation.allFinite() || !b.position.allFinite() ||
      !b.rotation.allFinite())
    throw std::invalid_argument("elliptic_torus_distance: non-finite torus pose");
  const Surface sa = surface_of(a), sb = surface_of(b);
  const int nu = std::max(4, options.surface_samples), nv = std::max(4, nu / 2), n = nu * nv;
  auto params = [&](int k) {
    return Eigen::Vector2d(2.0 * M_PI * (k / nv) / nu, 2.0 * M_PI * (k % nv) / nv);
  };
  std::vector<Eigen::Vector3d> pa(static_cast<std::size_t>(n)), pb(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector2d t = params(k);
    pa[static_cast<std::size_t>(k)] = point_of(sa, t[0], t[1]);
    pb[static_cast<std::size_t>(k)] = point_of(sb, t[0], t[1]);
  }
  // Every pair of samples: for each sample of a the nearest sample of b.
  std::vector<double> value(static_cast<std::size_t>(n));
  std::vector<int> nearest(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    double best = std::numeric_limits<double>::infinity();
    int arg = 0;
    for (int j = 0; j < n; ++j) {
      const double f = (pa[static_cast<std::size_t>(i)] - pb[static_cast<std::size_t>(j)]).squaredNorm();
      if (f < best) {
        best = f;
        arg = j;
      }
    }
    value[static_cast<std::size_t>(i)] = best;
    nearest[static_cast<std::size_t>(i)] = arg;
  }
  // Local minima over a's periodic (u, v) grid, lowest first.
  std::vector<int> minima;
  for (int i = 0; i < n; ++i) {
    const int iu = i / nv, iv = i % nv;
    const double v0 = value[static_cast<std::size_t>(i)];
    const int neighbours[4] = {((iu + 1) % nu) * nv + iv, ((iu + nu - 1) % nu) * nv + iv,
                               iu * nv + (iv + 1) % nv, iu * nv + (iv + nv - 1) % nv};
    bool lowest = true;
    for (int m : neighbours) lowest = lowest && v0 <= value[static_cast<std::size_t>(m)];
    if (lowest) minima.push_back(i);
  }
  std::sort(minima.begin(), minima.end(), [&](int i, int j) {
    return value[static_cast<std::size_t>(i)] < value[static_cast<std::size_t>(j)];
  });
  if (minima.empty()) minima.push_back(0);
  if (static_cast<int>(minima.size()) > options.surface_starts)
    minima.resize(static_cast<std::size_t>(std::max(1, options.surface_starts)));

  auto f = [&](const Vector4& u, Vector4* g, Matrix4* H) { return pair_function(sa, sb, u, g, H); };
  TorusDistance out;
  out.core_distance = std::numeric_limits<double>::quiet_NaN();
  double best = std::numeric_limits<double>::infinity();
  Vector4 u_best = Vector4::Zero();
  for (int i : minima) {
    Vector4 u;
    u << params(i), params(nearest[static_cast<std::size_t>(i)]);
    const double value_i = newton_minimize<4>(f, u, options.max_iterations);
    if (value_i < best) {
      best = value_i;
      u_best = u;
    }
  }
  out.theta_a = u_best[0];
  out.tube_a = u_best[1];
  out.theta_b = u_best[2];
  out.tube_b = u_best[3];
  out.distance = std::sqrt(best);

  // Overlap by the implicit functions: the samples, then Newton on each surface from its
  // closest point and its deepest sample.
  int deepest_a = 0, deepest_b = 0;
  double ga = std::numeric_limits<double>::infinity(), gb = ga;  // g_b on a's samples, g_a on b's
  for (int k = 0; k < n; ++k) {
    const double va = implicit_of(sb, pa[static_cast<std::size_t>(k)], nullptr, nullptr);
    const double vb = implicit_of(sa, pb[static_cast<std::size_t>(k)], nullptr, nullptr);
    if (va < ga) {
      ga = va;
      deepest_a = k;
    }
    if (vb < gb) {
      gb = vb;
      deepest_b = k;
    }
  }
  const int iterations = std::min(options.max_iterations, 20);
  ga = std::min(ga, smallest_implicit(sa, sb, {u_best.head<2>(), params(deepest_a)}, iterations));
  gb = std::min(gb, smallest_implicit(sb, sa, {u_best.tail<2>(), params(deepest_b)}, iterations));
  if (ga < 0.0 || gb < 0.0) {
    out.overlapping = true;
    out.degenerate = true;
    const double depth = std::max(-ga * std::min(sb.r, sb.r1), -gb * std::min(sa.r, sa.r1)) / 2.0;
    out.distance = -depth;
    return out;
  }

  Vector4 g;
  Matrix4 H;
  pair_function(sa, sb, u_best, &g, &H);
  const Vector4 lambda = symmetric_eigenvalues(H);
  out.degenerate = !(lambda[0] > 1e-9 * lambda.cwiseAbs().maxCoeff()) || !(out.distance > 0.0);
  if (!derivatives || out.degenerate) return out;

  const std::array<PairJet, 3> xa = surface_point_jet(a, u_best[0], u_best[1], 0, 4, 7, 16);
  const std::array<PairJet, 3> xb = surface_point_jet(b, u_best[2], u_best[3], 2, 10, 13, 19);
  PairJet fj = PairJet(0.0);
  for (int j = 0; j < 3; ++j) {
    const PairJet delta = xa[j] - xb[j];
    fj = fj + delta * delta;
  }
  // Implicit function theorem on f_u = 0 (elliptic_distance.hpp).
  Eigen::Matrix<double, 18, 1> gd;
  Eigen::Matrix<double, 18, 18> Hd;
  sqrt_minimum_derivatives<4, 18>(fj, out.distance, options.implicit_correction, gd, Hd);
  // Jet variables 4..21 -> pair variables: the DOFs 0..11, R_a 12, r_a 13, R_b 14, r_b 15; r1 of
  // a and b (jet 18 and 21) -> axial_gradient.
  const int map[18] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, -1, 14, 15, -2};
  for (int i = 0; i < 18; ++i) {
    if (map[i] < 0) {
      out.axial_gradient[-map[i] - 1] = is_elliptic(i < 15 ? a.shape : b.shape) ? gd[i] : 0.0;
      continue;
    }
    out.gradient[map[i]] = gd[i];
    for (int j = 0; j < 18; ++j)
      if (map[j] >= 0) out.hessian(map[i], map[j]) = Hd(i, j);
  }
  return out;
}

}  // namespace tailor::tori
