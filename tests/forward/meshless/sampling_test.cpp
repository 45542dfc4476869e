// Nodes and clipped octree quadrature of analytic solids (forward/meshless/octree_sampling.hpp):
// Gauss-Legendre exactness, the box sampled exactly, the sphere's volume converging as the
// boundary cells are refined (the table is printed; docs/meshless.md quotes it), the cylinder,
// and bad options.
#include "forward/meshless/octree_sampling.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace tailor::sampling_test {
namespace {

TEST(GaussLegendre, IntegratesPolynomialsOfDegreeTwoNMinusOneExactly) {
  for (int n = 1; n <= 8; ++n) {
    std::vector<double> x, w;
    gauss_legendre(n, x, w);
    for (int degree = 0; degree <= 2 * n - 1; ++degree) {
      double s = 0.0;
      for (int i = 0; i < n; ++i) s += w[static_cast<std::size_t>(i)] * std::pow(x[static_cast<std::size_t>(i)], degree);
      const double exact = degree % 2 == 1 ? 0.0 : 2.0 / (degree + 1);
      EXPECT_NEAR(s, exact, 1e-14) << "order " << n << ", degree " << degree;
    }
    // Degree 2n is not exact: the rule is the one of order n.
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += w[static_cast<std::size_t>(i)] * std::pow(x[static_cast<std::size_t>(i)], 2 * n);
    EXPECT_GT(std::abs(s - 2.0 / (2 * n + 1)), 1e-6) << "order " << n;
  }
}

TEST(OctreeSampling, BoxNodesOnTheLatticeAndVolumeExact) {
  const AnalyticShape box = box_shape(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1));
  const OctreeSampling s = sample_shape(box, {0.5, 2, 0});
  EXPECT_EQ(s.nodes.rows(), 5 * 3 * 3);
  EXPECT_EQ(s.points.rows(), 16 * 8);
  EXPECT_NEAR(s.volume(), 2.0, 1e-14);
  // Every node and point lies in the closed box.
  for (Eigen::Index a = 0; a < s.nodes.rows(); ++a) EXPECT_LE(box.signed_distance(s.nodes.row(a).transpose()), 1e-12);
  for (Eigen::Index q = 0; q < s.points.rows(); ++q) EXPECT_LT(box.signed_distance(s.points.row(q).transpose()), 0.0);
}

// The sphere's volume as the cut cells are refined. The error is not monotone level by level
// (the clipped leaves' errors have both signs and cancel by chance: 1.6e-4 at depth 1, 5.7e-4 at
// depth 2), but falls from 2.6e-2 at depth 0 to 1.4e-5 at depth 5, an overall rate of 2.2 per
// level; the table is the figure of docs/meshless.md.
TEST(OctreeSampling, SphereVolumeConvergesWithBoundaryDepth) {
  const double r = 1.0;
  const AnalyticShape ball = sphere_shape(Eigen::Vector3d(0.1, -0.05, 0.02), r);
  const double exact = 4.0 / 3.0 * M_PI * r * r * r;
  std::printf("sphere r = 1, spacing 0.25, 2 Gauss points per axis\n%6s %10s %12s %12s %8s\n", "depth", "points",
              "volume", "rel. error", "rate");
  std::vector<double> errors;
  for (int depth = 0; depth <= 5; ++depth) {
    const OctreeSampling s = sample_shape(ball, {0.25, 2, depth});
    const double error = std::abs(s.volume() - exact) / exact;
    const double rate = errors.empty() ? NAN : std::log2(errors.back() / error);
    std::printf("%6d %10d %12.8f %12.3e %8.2f\n", depth, static_cast<int>(s.points.rows()), s.volume(), error, rate);
    errors.push_back(error);
  }
  // Overall rate from depth 0 to 5 at least 1.5 per level, from depth 2 to 5 at least 1, and the
  // finest below 1e-4.
  EXPECT_GT(std::log2(errors.front() / errors.back()) / 5.0, 1.5);
  EXPECT_GT(std::log2(errors[2] / errors.back()) / 3.0, 1.0);
  EXPECT_LT(errors.back(), 1e-4);
  // Nodes all inside the ball.
  const OctreeSampling s = sample_shape(ball, {0.25, 2, 1});
  for (Eigen::Index a = 0; a < s.nodes.rows(); ++a) EXPECT_LE(ball.signed_distance(s.nodes.row(a).transpose()), 1e-12);
  EXPECT_GT(s.cells_cut, 0);
  EXPECT_GT(s.cells_inside, 0);
}

TEST(OctreeSampling, CylinderVolume) {
  const AnalyticShape c = cylinder_shape(Eigen::Vector3d(0, 0, 0), 0.5, 2.0, 0);
  EXPECT_NEAR(c.signed_distance(Eigen::Vector3d(0, 0, 0)), -0.5, 1e-15);
  EXPECT_NEAR(c.signed_distance(Eigen::Vector3d(1.5, 0, 0)), 0.5, 1e-15);
  EXPECT_NEAR(c.signed_distance(Eigen::Vector3d(0.9, 0.3, 0)), -0.1, 1e-15);
  const OctreeSampling s = sample_shape(c, {0.125, 2, 4});
  EXPECT_NEAR(s.volume(), c.exact_volume, 2e-3 * c.exact_volume);
}

TEST(OctreeSampling, ShellOctantVolume) {
  const AnalyticShape shell = shell_octant_shape(Eigen::Vector3d::Zero(), 1.0, 2.0);
  EXPECT_NEAR(shell.signed_distance(Eigen::Vector3d(1.5, 0.3, 0.2).normalized() * 1.5), -0.2 / std::sqrt(1.5 * 1.5 + 0.09 + 0.04) * 1.5, 1e-12);
  EXPECT_GT(shell.signed_distance(Eigen::Vector3d(-0.1, 1.5, 0.5)), 0.0);
  EXPECT_GT(shell.signed_distance(Eigen::Vector3d(0.3, 0.3, 0.3)), 0.0);
  const OctreeSampling s = sample_shape(shell, {0.25, 2, 3});
  EXPECT_NEAR(s.volume(), shell.exact_volume, 2e-3 * shell.exact_volume);
  for (Eigen::Index a = 0; a < s.nodes.rows(); ++a) EXPECT_LE(shell.signed_distance(s.nodes.row(a).transpose()), 1e-12);
}

TEST(OctreeSampling, RefusesBadOptions) {
  const AnalyticShape ball = sphere_shape(Eigen::Vector3d::Zero(), 1.0);
  EXPECT_THROW(sample_shape(ball, {0.0, 2, 1}), std::invalid_argument);
  EXPECT_THROW(sample_shape(ball, {0.5, 0, 1}), std::invalid_argument);
  EXPECT_THROW(sample_shape(ball, {0.5, 2, 9}), std::invalid_argument);
  EXPECT_THROW(sphere_shape(Eigen::Vector3d::Zero(), -1.0), std::invalid_argument);
  EXPECT_THROW(box_shape(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 1)), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::sampling_test
