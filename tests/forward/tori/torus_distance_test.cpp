// Torus distance: closed-form configurations, a dense-sampling reference for random
// interlocked pairs, and derivative checks of the implicit-function-theorem gradient/Hessian.
#include "forward/tori/torus_distance.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "forward/rigid/rotation.hpp"

namespace tailor::tori::torus_distance_test {
namespace {

// Brute force: over n angles of a, the exact distance of a's core point to b's core circle
// (point-circle distance: sqrt(h^2 + (rho - R_b)^2), h the height over b's plane, rho the
// distance from b's axis), the smallest of them. It can only overestimate the global minimum,
// by O(n^-2) of the distance's curvature along a.
double sampled_core_distance(const TorusPose& a, const TorusPose& b, int n) {
  const Eigen::Matrix3d Q = rigid::rotation_matrix(b.rotation);
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d v = core_point(a, 2 * M_PI * i / n) - b.position;
    const double h = v.dot(Q.col(2)), rho = (v - h * Q.col(2)).norm();
    best = std::min(best, std::hypot(h, rho - b.shape.major_radius));
  }
  return best;
}

TEST(TorusDistance, HangingLinkMatchesTheClosedForm) {
  // a in the xz plane at the origin, b in the yz plane below it at depth s: the core circles'
  // closest points are a's bottom and b's top, D = |2R - s| (docs/tori.md).
  const double R = 1.0, r = 0.2, s = 1.5;
  const TorusPose a{Eigen::Vector3d::Zero(), Eigen::Vector3d(M_PI / 2, 0, 0), {R, r}};
  const TorusPose b{Eigen::Vector3d(0, 0, -s), Eigen::Vector3d(0, M_PI / 2, 0), {R, r}};
  const TorusDistance d = torus_distance(a, b, true);
  EXPECT_NEAR(d.core_distance, 2 * R - s, 1e-12);
  EXPECT_NEAR(d.distance, 2 * R - s - 2 * r, 1e-12);
  EXPECT_FALSE(d.degenerate);
  // Interlocked: b's top core point lies above a's bottom one. Raising b (or lowering a) opens
  // the gap at rate 1; a larger R_a lowers a's bottom, a larger R_b raises b's top: both open it.
  EXPECT_NEAR(d.gradient[8], 1.0, 1e-10);
  EXPECT_NEAR(d.gradient[2], -1.0, 1e-10);
  EXPECT_EQ(d.gradient[13], -1.0);
  EXPECT_NEAR(d.gradient[12], 1.0, 1e-10);
  EXPECT_NEAR(d.gradient[14], 1.0, 1e-10);
}

TEST(TorusDistance, RandomPairsAgreeWithDenseSampling) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int checked = 0;
  for (int k = 0; k < 200; ++k) {
    const TorusPose a{Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.8, Eigen::Vector3d(u(rng), u(rng), u(rng)) * 2.0,
                      {1.0, 0.2}};
    const TorusPose b{Eigen::Vector3d(u(rng), u(rng), u(rng)) * 1.5, Eigen::Vector3d(u(rng), u(rng), u(rng)) * 2.0,
                      {0.8 + 0.3 * std::abs(u(rng)), 0.15}};
    const TorusDistance d = torus_distance(a, b, false);
    const double reference = sampled_core_distance(a, b, 20000);
    // Ours is a value of f at actual angles, so never below the true minimum; the reference
    // overestimates D^2 (smooth in the angle) by O(1e-7) here. Missing the global minimum would
    // put ours far above.
    EXPECT_LE(d.core_distance, reference + 1e-12) << k;
    EXPECT_GE(d.core_distance * d.core_distance, reference * reference - 1e-6) << k;
    ++checked;
  }
  EXPECT_EQ(checked, 200);
}

}  // namespace
}  // namespace tailor::tori::torus_distance_test
