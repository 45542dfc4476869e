// Distances, barrier and mollifier of IPC (Li et al. 2020): every branch's exact derivatives
// against central differences, and the classified distance against a brute-force minimum
// over sampled points of the two primitives (the reference: the definition of the distance).
#include <gtest/gtest.h>

#include <random>

#include "finite_difference.hpp"
#include "forward/contact/barrier.hpp"
#include "forward/contact/pair_potential.hpp"

namespace tailor::contact::distance_test {
namespace {

using testing::fd_gradient;
using testing::fd_jacobian;
using testing::relative_error;
using Stencil = std::array<Point, 4>;

Eigen::VectorXd flatten(const Stencil& s) {
  Eigen::VectorXd x(12);
  for (int k = 0; k < 4; ++k) x.segment<3>(3 * k) = s[k];
  return x;
}
Stencil unflatten(const Eigen::VectorXd& x) {
  return {x.segment<3>(0), x.segment<3>(3), x.segment<3>(6), x.segment<3>(9)};
}

// The branch formula (classification frozen at x) with its jet derivatives vs differences.
void check_branch(const ClassifiedDistance& c, const Stencil& s) {
  const Eigen::VectorXd x = flatten(s);
  const Dual2<12> jet = squared_distance_jet(c, s);
  EXPECT_NEAR(jet.v, c.squared_distance, 1e-12 * std::max(1.0, c.squared_distance));
  auto value = [&](const Eigen::VectorXd& y) {
    return branch_squared_distance(c, stencil_values(unflatten(y)));
  };
  auto gradient = [&](const Eigen::VectorXd& y) -> Eigen::VectorXd {
    return squared_distance_jet(c, unflatten(y)).g;
  };
  EXPECT_LT(relative_error(jet.g, fd_gradient(value, x, 1e-6)), 1e-7) << to_string(c.branch);
  EXPECT_LT(relative_error(jet.h, fd_jacobian(gradient, x, 1e-6)), 1e-7) << to_string(c.branch);
}

// min over a grid of barycentric / segment parameters (an upper bound of the true distance
// that converges to it as the grid refines).
double sampled_point_triangle(const Stencil& s, int n) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const double u = double(i) / n, v = double(j) / n;
      best = std::min(best, (s[0] - (s[1] + u * (s[2] - s[1]) + v * (s[3] - s[1]))).squaredNorm());
    }
  return best;
}
double sampled_edge_edge(const Stencil& s, int n) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double u = double(i) / n, v = double(j) / n;
      best = std::min(best, ((s[0] + u * (s[1] - s[0])) - (s[2] + v * (s[3] - s[2]))).squaredNorm());
    }
  return best;
}

TEST(ContactDistance, PointTriangleEveryBranchHasExactDerivatives) {
  const Point t0(0, 0, 0), t1(1, 0, 0), t2(0, 1, 0);
  struct Case {
    Point p;
    DistanceBranch branch;
  };
  const std::vector<Case> cases = {{Point(0.2, 0.3, 0.4), DistanceBranch::point_plane},
                                   {Point(0.5, -0.3, 0.2), DistanceBranch::point_edge},
                                   {Point(0.7, 0.6, -0.1), DistanceBranch::point_edge},  // hypotenuse
                                   {Point(-0.3, 0.4, 0.1), DistanceBranch::point_edge},
                                   {Point(-0.2, -0.3, 0.3), DistanceBranch::point_point},
                                   {Point(1.4, -0.1, 0.2), DistanceBranch::point_point},
                                   {Point(-0.1, 1.3, -0.2), DistanceBranch::point_point}};
  for (const Case& k : cases) {
    const Stencil s{k.p, t0, t1, t2};
    const ClassifiedDistance c = classify_point_triangle(s[0], s[1], s[2], s[3]);
    EXPECT_EQ(c.branch, k.branch) << k.p.transpose();
    EXPECT_NEAR(c.squared_distance, sampled_point_triangle(s, 400), 1e-4);
    check_branch(c, s);
  }
}

TEST(ContactDistance, EdgeEdgeEveryBranchHasExactDerivatives) {
  const Point a0(0, 0, 0), a1(1, 0, 0);
  struct Case {
    Point b0, b1;
    DistanceBranch branch;
  };
  const std::vector<Case> cases = {
      {Point(0.5, -0.5, 0.3), Point(0.4, 0.6, 0.25), DistanceBranch::line_line},
      {Point(1.3, -0.5, 0.3), Point(1.3, 0.6, 0.25), DistanceBranch::point_edge},  // a1 to edge b
      {Point(0.5, 0.2, 0.3), Point(0.6, 1.0, 0.25), DistanceBranch::point_edge},   // b0 to edge a
      {Point(1.3, 0.2, 0.3), Point(1.9, 1.0, 0.25), DistanceBranch::point_point},  // a1 to b0
      {Point(0.2, 0.0, 0.3), Point(0.8, 0.0, 0.3), DistanceBranch::point_edge},    // exactly parallel
  };
  for (const Case& k : cases) {
    const Stencil s{a0, a1, k.b0, k.b1};
    const ClassifiedDistance c = classify_edge_edge(s[0], s[1], s[2], s[3]);
    EXPECT_EQ(c.branch, k.branch) << k.b0.transpose() << " / " << k.b1.transpose();
    EXPECT_NEAR(c.squared_distance, sampled_edge_edge(s, 400), 1e-4);
    check_branch(c, s);
  }
}

TEST(ContactDistance, ClassificationMatchesBruteForceOnRandomPairs) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto point = [&] { return Point(u(rng), u(rng), u(rng)); };
  for (int trial = 0; trial < 200; ++trial) {
    const Stencil s{point(), point(), point(), point()};
    const double pt = classify_point_triangle(s[0], s[1], s[2], s[3]).squared_distance;
    const double ee = classify_edge_edge(s[0], s[1], s[2], s[3]).squared_distance;
    const double pt_sampled = sampled_point_triangle(s, 120), ee_sampled = sampled_edge_edge(s, 120);
    // The sampled minimum bounds the true one from above, within the grid's resolution.
    EXPECT_LE(pt, pt_sampled + 1e-12);
    EXPECT_LE(ee, ee_sampled + 1e-12);
    EXPECT_LT(pt_sampled - pt, 2e-3);
    EXPECT_LT(ee_sampled - ee, 2e-3);
  }
}

TEST(ContactBarrier, DerivativesAndSmoothActivation) {
  const double s_hat = 1e-2;
  for (double s : {1e-6, 1e-4, 3e-3, 9.9e-3}) {
    const ScalarDerivatives b = barrier(s, s_hat);
    const double h = 1e-7 * s;
    EXPECT_NEAR(b.first, (barrier(s + h, s_hat).value - barrier(s - h, s_hat).value) / (2 * h),
                1e-6 * std::abs(b.first));
    EXPECT_NEAR(b.second, (barrier(s + h, s_hat).first - barrier(s - h, s_hat).first) / (2 * h),
                1e-6 * std::abs(b.second));
    EXPECT_GT(b.value, 0.0);
    EXPECT_LT(b.first, 0.0);  // repulsive
  }
  const ScalarDerivatives edge = barrier(s_hat * (1 - 1e-9), s_hat);
  EXPECT_LT(std::abs(edge.value), 1e-20);
  EXPECT_LT(std::abs(edge.first), 1e-12);
  EXPECT_LT(std::abs(edge.second), 1e-7);
  EXPECT_EQ(barrier(s_hat, s_hat).value, 0.0);
  EXPECT_TRUE(std::isinf(barrier(0.0, s_hat).value));
}

TEST(ContactMollifier, DerivativesAndContinuity) {
  const double eps = 2e-4;
  for (double c : {1e-7, 5e-5, 1.9e-4}) {
    const ScalarDerivatives m = edge_mollifier(c, eps);
    const double h = 1e-6 * c;
    EXPECT_NEAR(m.first, (edge_mollifier(c + h, eps).value - edge_mollifier(c - h, eps).value) / (2 * h),
                1e-6 * std::abs(m.first));
    EXPECT_NEAR(m.second, (edge_mollifier(c + h, eps).first - edge_mollifier(c - h, eps).first) / (2 * h),
                1e-5 * std::abs(m.second));
  }
  EXPECT_NEAR(edge_mollifier(eps * (1 - 1e-12), eps).value, 1.0, 1e-12);
  EXPECT_NEAR(edge_mollifier(eps * (1 - 1e-12), eps).first, 0.0, 1e-6 / eps);
}

// The pair barrier (value without derivatives) vs its jet gradient and Hessian.
void check_pair(PairKind kind, const Stencil& s, double s_hat, double eps, DistanceBranch branch,
                bool mollified) {
  PairDerivatives d;
  ASSERT_TRUE(pair_barrier(kind, s, s_hat, eps, true, d));
  EXPECT_EQ(d.distance.branch, branch);
  EXPECT_EQ(d.mollified, mollified);
  const double h = 1e-7;
  auto value = [&](const Eigen::VectorXd& y) {
    PairDerivatives e;
    pair_barrier(kind, unflatten(y), s_hat, eps, false, e);
    return e.value;
  };
  auto gradient = [&](const Eigen::VectorXd& y) -> Eigen::VectorXd {
    PairDerivatives e;
    pair_barrier(kind, unflatten(y), s_hat, eps, true, e);
    return e.gradient;
  };
  const Eigen::VectorXd x = flatten(s);
  EXPECT_LT(relative_error(d.gradient, fd_gradient(value, x, h)), 1e-6) << to_string(branch);
  EXPECT_LT(relative_error(d.hessian, fd_jacobian(gradient, x, h)), 1e-6) << to_string(branch);
}

TEST(ContactPairBarrier, EveryBranchMollifiedOrNotHasExactDerivatives) {
  const double s_hat = 0.01;  // d_hat = 0.1
  const Point t0(0, 0, 0), t1(1, 0, 0), t2(0, 1, 0);
  check_pair(PairKind::point_triangle, {Point(0.2, 0.3, 0.05), t0, t1, t2}, s_hat, 0,
             DistanceBranch::point_plane, false);
  check_pair(PairKind::point_triangle, {Point(0.5, -0.04, 0.05), t0, t1, t2}, s_hat, 0,
             DistanceBranch::point_edge, false);
  check_pair(PairKind::point_triangle, {Point(-0.03, -0.04, 0.05), t0, t1, t2}, s_hat, 0,
             DistanceBranch::point_point, false);
  const Point a0(0, 0, 0), a1(1, 0, 0);
  const double rest = mollifier_threshold(1.0, 0.36);
  // Crossing edges: not mollified, every branch.
  check_pair(PairKind::edge_edge, {a0, a1, Point(0.5, -0.3, 0.05), Point(0.5, 0.3, 0.06)}, s_hat, rest,
             DistanceBranch::line_line, false);
  check_pair(PairKind::edge_edge, {a0, a1, Point(1.05, -0.3, 0.05), Point(1.05, 0.3, 0.06)}, s_hat, rest,
             DistanceBranch::point_edge, false);
  check_pair(PairKind::edge_edge, {a0, a1, Point(1.03, 0.02, 0.05), Point(1.03, 0.6, 0.06)}, s_hat, rest,
             DistanceBranch::point_point, false);
  // Nearly parallel edges (c = 1e-4 < eps = 3.6e-4): mollified, every branch.
  check_pair(PairKind::edge_edge, {a0, a1, Point(0.2, -0.005, 0.05), Point(0.8, 0.005, 0.05)}, s_hat, rest,
             DistanceBranch::line_line, true);
  check_pair(PairKind::edge_edge, {a0, a1, Point(0.9, -0.005, 0.05), Point(1.5, 0.005, 0.05)}, s_hat, rest,
             DistanceBranch::point_edge, true);
  check_pair(PairKind::edge_edge, {a0, a1, Point(1.02, -0.005, 0.05), Point(1.62, 0.005, 0.05)}, s_hat, rest,
             DistanceBranch::point_point, true);
}

// The check can fail: the product rule with a flipped sign on the mollifier's shape
// derivative (the historical bug) is caught by the same comparison.
TEST(ContactPairBarrier, FlippedMollifierDerivativeIsCaught) {
  const double s_hat = 0.01, eps = mollifier_threshold(1.0, 0.36);
  const Stencil s{Point(0, 0, 0), Point(1, 0, 0), Point(0.2, -0.005, 0.05), Point(0.8, 0.005, 0.05)};
  const auto jets = stencil_jets(s);
  const ClassifiedDistance c = classify_edge_edge(s[0], s[1], s[2], s[3]);
  const Dual2<12> d = branch_squared_distance(c, jets);
  const Dual2<12> cross = edge_cross_squared(jets[0], jets[1], jets[2], jets[3]);
  const ScalarDerivatives b = barrier(d.v, s_hat), m = edge_mollifier(cross.v, eps);
  const Eigen::Matrix<double, 12, 1> wrong = m.value * b.first * d.g - b.value * m.first * cross.g;
  auto value = [&](const Eigen::VectorXd& y) {
    PairDerivatives e;
    pair_barrier(PairKind::edge_edge, unflatten(y), s_hat, eps, false, e);
    return e.value;
  };
  const Eigen::VectorXd reference = fd_gradient(value, flatten(s), 1e-7);
  EXPECT_GT(relative_error(wrong, reference), 1e-2);
  PairDerivatives right;
  pair_barrier(PairKind::edge_edge, s, s_hat, eps, true, right);
  EXPECT_LT(relative_error(right.gradient, reference), 1e-6);
}

TEST(ContactPairBarrier, InactiveBeyondActivationDistance) {
  PairDerivatives d;
  EXPECT_FALSE(pair_barrier(PairKind::point_triangle,
                            {Point(0.2, 0.2, 0.2), Point(0, 0, 0), Point(1, 0, 0), Point(0, 1, 0)}, 0.01, 0,
                            true, d));
  EXPECT_EQ(d.value, 0.0);
}

}  // namespace
}  // namespace tailor::contact::distance_test
