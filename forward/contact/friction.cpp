// Smoothed, lagged IPC friction per pair (see friction.hpp).
#include "forward/contact/friction.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "forward/contact/barrier.hpp"

namespace tailor::contact {

PairTangent pair_tangent(const ClassifiedDistance& distance, const std::array<Point, 4>& points) {
  PairTangent t;
  const auto& i = distance.points;
  auto P = [&](int k) -> const Point& {
    return points[static_cast<std::size_t>(i[static_cast<std::size_t>(k)])];
  };
  auto weight = [&](int k) -> double& {
    return t.weights[static_cast<std::size_t>(i[static_cast<std::size_t>(k)])];
  };
  switch (distance.branch) {
    case DistanceBranch::point_point:
      weight(0) = 1.0;
      weight(1) = -1.0;
      break;
    case DistanceBranch::point_edge: {
      const Point e = P(2) - P(1);
      const double a = std::clamp((P(0) - P(1)).dot(e) / e.squaredNorm(), 0.0, 1.0);
      weight(0) = 1.0;
      weight(1) = -(1.0 - a);
      weight(2) = -a;
      break;
    }
    case DistanceBranch::point_plane: {
      Eigen::Matrix<double, 3, 2> E;
      E << P(2) - P(1), P(3) - P(1);
      const Eigen::Vector2d beta = (E.transpose() * E).ldlt().solve(E.transpose() * (P(0) - P(1)));
      weight(0) = 1.0;
      weight(1) = -(1.0 - beta[0] - beta[1]);
      weight(2) = -beta[0];
      weight(3) = -beta[1];
      break;
    }
    case DistanceBranch::line_line: {
      const Point u = P(1) - P(0), v = P(3) - P(2), w0 = P(0) - P(2);
      const double a = u.dot(u), b = u.dot(v), c = v.dot(v), d = u.dot(w0), e = v.dot(w0);
      const double den = a * c - b * b;
      const double s = (b * e - c * d) / den, r = (a * e - b * d) / den;
      weight(0) = 1.0 - s;
      weight(1) = s;
      weight(2) = -(1.0 - r);
      weight(3) = -r;
      break;
    }
  }
  Point r = Point::Zero();
  for (int k = 0; k < 4; ++k)
    r += t.weights[static_cast<std::size_t>(k)] * points[static_cast<std::size_t>(k)];
  t.normal = r.normalized();
  const Eigen::Matrix<double, 3, 2> basis = tangent_basis(t.normal);
  const Point t1 = basis.col(0), t2 = basis.col(1);
  for (int k = 0; k < 4; ++k) {
    t.tangent.block<1, 3>(0, 3 * k) = t.weights[static_cast<std::size_t>(k)] * t1.transpose();
    t.tangent.block<1, 3>(1, 3 * k) = t.weights[static_cast<std::size_t>(k)] * t2.transpose();
  }
  return t;
}

Eigen::Matrix<double, 3, 2> tangent_basis(const Eigen::Vector3d& normal) {
  // Started from the axis least aligned with n.
  Eigen::Index axis = 0;
  normal.cwiseAbs().minCoeff(&axis);
  Eigen::Matrix<double, 3, 2> basis;
  basis.col(0) = normal.cross(Point::Unit(axis)).normalized();
  basis.col(1) = normal.cross(Eigen::Vector3d(basis.col(0)));
  return basis;
}

double friction_f0(double y, double eps) {
  if (y >= eps) return y;
  return y * y * y / (-3.0 * eps * eps) + y * y / eps + eps / 3.0;
}

double friction_f1(double y, double eps) {
  if (y >= eps) return 1.0;
  return 2.0 * y / eps - y * y / (eps * eps);
}

namespace {
std::array<Point, 4> stencil_points(const Positions& x, const std::array<int, 4>& v) {
  return {x.row(v[0]).transpose(), x.row(v[1]).transpose(), x.row(v[2]).transpose(), x.row(v[3]).transpose()};
}
}  // namespace

std::vector<FrictionPair> lag_friction_pairs(const ContactPotential& potential, const Positions& x_lag,
                                             const Positions& x_start) {
  const double d_hat = potential.options().activation_distance, s_hat = d_hat * d_hat;
  const double kappa = potential.options().stiffness;
  const CandidatePairs candidates = find_candidates(potential.surface(), x_lag, d_hat);
  std::vector<FrictionPair> pairs;
  auto run = [&](PairKind kind, const std::array<int, 2>& candidate) {
    FrictionPair pair;
    pair.kind = kind;
    pair.vertices = potential.stencil(kind, candidate);
    const std::array<Point, 4> points = stencil_points(x_lag, pair.vertices);
    const ClassifiedDistance distance = classify_pair(kind, points);
    const double s = distance.squared_distance;
    if (!(s < s_hat) || !(s > 0.0)) return;
    double mollifier = 1.0;
    if (kind == PairKind::edge_edge) {
      const double cross = (points[1] - points[0]).cross(points[3] - points[2]).squaredNorm();
      mollifier = edge_mollifier(cross, potential.mollifier_eps(candidate)).value;
    }
    pair.normal_force = kappa * mollifier * std::abs(barrier(s, s_hat).first) * 2.0 * std::sqrt(s);
    if (!(pair.normal_force > 0.0)) return;
    pair.tangent = pair_tangent(distance, points).tangent;
    const std::array<Point, 4> start = stencil_points(x_start, pair.vertices);
    for (int k = 0; k < 4; ++k) pair.start.segment<3>(3 * k) = start[static_cast<std::size_t>(k)];
    pairs.push_back(pair);
  };
  for (const auto& c : candidates.point_triangle) run(PairKind::point_triangle, c);
  for (const auto& c : candidates.edge_edge) run(PairKind::edge_edge, c);
  return pairs;
}

FrictionDerivatives friction_pair_potential(const FrictionPair& pair, const Eigen::Matrix<double, 12, 1>& x,
                                            double mu, double eps, bool derivatives) {
  FrictionDerivatives out;
  const Eigen::Vector2d u = pair.tangent * (x - pair.start);
  const double y = u.norm(), scale = mu * pair.normal_force;
  out.slip = y;
  out.value = scale * friction_f0(y, eps);
  if (!derivatives) return out;
  // f1(y) / y and (d/dy (f1(y) / y)) / y, both finite at y = 0 on the smoothed branch.
  const double f1_over_y = y < eps ? 2.0 / eps - y / (eps * eps) : 1.0 / y;
  const Eigen::Vector2d force = scale * f1_over_y * u;
  out.gradient = pair.tangent.transpose() * force;
  Eigen::Matrix2d Hu = f1_over_y * Eigen::Matrix2d::Identity();
  if (y > 0.0) Hu -= (y < eps ? 1.0 / (eps * eps * y) : 1.0 / (y * y * y)) * u * u.transpose();
  out.hessian = scale * pair.tangent.transpose() * Hu * pair.tangent;
  return out;
}

}  // namespace tailor::contact
