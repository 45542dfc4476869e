// Nodes and clipped octree quadrature of analytic solids (forward/meshless/octree_sampling.hpp):
// Gauss-Legendre exactness, the box sampled exactly, the sphere's volume converging as the
// boundary cells are refined (the table is printed; docs/meshless.md quotes it), the cylinder,
// bad options; adaptive node levels in a thin fin with patches sized for covering
// (forward/meshless/covering_patches.hpp) and the patch test on the mixed supports.
#include "forward/meshless/octree_sampling.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "forward/meshless/covering_patches.hpp"
#include "forward/meshless/mls_shape_functions.hpp"

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
  EXPECT_THROW(sample_shape(ball, {0.5, 2, 1, 7}), std::invalid_argument);
  EXPECT_THROW(sample_shape(ball, {0.5, 2, 1, 1, true, {{Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 2}}}),
               std::invalid_argument);
  EXPECT_THROW(sphere_shape(Eigen::Vector3d::Zero(), -1.0), std::invalid_argument);
  EXPECT_THROW(box_shape(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 1)), std::invalid_argument);
}

// A block 2 x 1 x 1 with a fin 1 x 1 x 0.1875 on its end face (x = 2 to 3, z = 0.375 to 0.5625): the
// union's signed distance min(d_block, d_fin) is 1-Lipschitz and no larger than the distance to
// the boundary, as the octree needs.
AnalyticShape block_with_fin() {
  const AnalyticShape block = box_shape(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1));
  const AnalyticShape fin = box_shape(Eigen::Vector3d(2, 0, 0.375), Eigen::Vector3d(3, 1, 0.5625));
  AnalyticShape shape;
  shape.name = "block with fin";
  shape.signed_distance = [block, fin](const Eigen::Vector3d& X) {
    return std::min(block.signed_distance(X), fin.signed_distance(X));
  };
  shape.lo = Eigen::Vector3d(0, 0, 0);
  shape.hi = Eigen::Vector3d(3, 1, 1);
  return shape;
}

// The patch test of MLS shape functions on `nodes` with per-node spacings `patches` at every
// quadrature point: the largest errors of sum phi_a = 1 and sum phi_a X_a = X (values), of
// sum grad phi_a = 0 and sum X_a grad phi_a^T = I (gradients), of F = I + G for x_a = X_a + G X_a;
// the fewest covering nodes and the largest condition number.
struct PatchTest {
  double worst_value = 0.0, worst_gradient = 0.0, worst_F = 0.0, worst_condition = 0.0;
  int fewest = 1 << 30;
};
PatchTest patch_test(const OctreeSampling& s, const Eigen::VectorXd& patches, const MlsOptions& mls) {
  PatchTest t;
  const MlsShapeFunctions shape_functions(s.nodes, patches, mls);
  const Eigen::Matrix3d G = (Eigen::Matrix3d() << 0.3, -0.2, 0.1, 0.05, 0.4, -0.3, 0.2, 0.1, -0.25).finished();
  for (Eigen::Index q = 0; q < s.points.rows(); ++q) {
    const Eigen::Vector3d X = s.points.row(q).transpose();
    const MlsValues v = shape_functions.evaluate(X);
    t.fewest = std::min(t.fewest, static_cast<int>(v.nodes.size()));
    t.worst_condition = std::max(t.worst_condition, v.condition);
    double unity = -1.0;
    Eigen::Vector3d position = -X, gradient_sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d identity = -Eigen::Matrix3d::Identity(), F = -(Eigen::Matrix3d::Identity() + G);
    for (std::size_t i = 0; i < v.nodes.size(); ++i) {
      const Eigen::Vector3d Xa = s.nodes.row(v.nodes[i]).transpose();
      const Eigen::Vector3d grad = v.gradients.row(static_cast<Eigen::Index>(i)).transpose();
      unity += v.values[static_cast<Eigen::Index>(i)];
      position += v.values[static_cast<Eigen::Index>(i)] * Xa;
      gradient_sum += grad;
      identity += Xa * grad.transpose();
      F += (Xa + G * Xa) * grad.transpose();
    }
    t.worst_value = std::max({t.worst_value, std::abs(unity), position.norm()});
    t.worst_gradient = std::max({t.worst_gradient, gradient_sum.norm(), identity.norm()});
    t.worst_F = std::max(t.worst_F, F.norm());
  }
  return t;
}

int nodes_in_fin(const OctreeSampling& s) {
  int count = 0;
  for (Eigen::Index a = 0; a < s.nodes.rows(); ++a) count += s.nodes(a, 0) > 2.0 + 1e-9;
  return count;
}

// With node spacing h = 0.25 the fin (0.1875 thick) holds one plane of nodes (z = 0.5): no
// linear basis exists from the fin's nodes alone, and a point near the fin's end is covered only
// by supports stretched across the whole fin to the block's face (one pass of enlargement is not
// enough: the point is refused, named). With max_level 2 the thin rule splits the fin's cells to
// h / 4 (four node layers, z = 0.375 to 0.5625), the block keeps h; the patches sized per node then
// cover every quadrature point without stretching, and the
// MLS shape functions with their mixed radii reproduce linear fields to round-off (the patch
// test: partition of unity, x, the gradients, and F = I + G for the displacement G X).
TEST(OctreeSampling, ThinFinGetsFinerNodesAndEveryPointIsCovered) {
  const AnalyticShape shape = block_with_fin();
  const OctreeSampling uniform = sample_shape(shape, {0.25, 2, 1});
  EXPECT_EQ(uniform.level.maxCoeff(), 0);
  CoveringOptions one_pass;
  one_pass.max_passes = 1;
  try {
    cover_points(uniform.nodes, uniform.spacing, uniform.points, MlsOptions{}, one_pass);
    ADD_FAILURE() << "the uniform nodes cover the fin";
  } catch (const MeshlessPointError& e) {
    EXPECT_GT(e.point()[0], 2.0) << e.what();
    EXPECT_NE(std::string(e.what()).find("covering: "), std::string::npos) << e.what();
  }
  CoveringReport stretched;
  const Eigen::VectorXd uniform_patches = cover_points(uniform.nodes, uniform.spacing, uniform.points, MlsOptions{}, {}, &stretched);
  std::printf("uniform nodes: %d points repaired, supports stretched up to %.2fx in %d passes\n", stretched.points_repaired,
              stretched.largest_growth, stretched.passes);
  EXPECT_GT(stretched.largest_growth, 2.0);

  OctreeSamplingOptions options{0.25, 2, 1};
  options.max_level = 2;
  const OctreeSampling s = sample_shape(shape, options);
  std::printf("block with fin: uniform %d nodes (%d in the fin), adaptive %d nodes (%d in the fin), %d cells split, "
              "%d quadrature points\n",
              static_cast<int>(uniform.nodes.rows()), nodes_in_fin(uniform), static_cast<int>(s.nodes.rows()),
              nodes_in_fin(s), s.cells_refined, static_cast<int>(s.points.rows()));
  EXPECT_GE(nodes_in_fin(s), 4 * nodes_in_fin(uniform));
  int block_nodes = 0, uniform_block_nodes = 0;
  for (Eigen::Index a = 0; a < s.nodes.rows(); ++a) {
    const Eigen::Vector3d X = s.nodes.row(a).transpose();
    EXPECT_LE(shape.signed_distance(X), 1e-12);
    if (X[0] > 2.0 + 1e-9) {
      EXPECT_EQ(s.level[a], 2) << X.transpose();
    }
    if (X[0] < 1.5) {
      EXPECT_EQ(s.level[a], 0) << X.transpose();
      ++block_nodes;
    }
  }
  for (Eigen::Index a = 0; a < uniform.nodes.rows(); ++a) uniform_block_nodes += uniform.nodes(a, 0) < 1.5;
  EXPECT_EQ(block_nodes, uniform_block_nodes);  // the thick block is not refined
  EXPECT_NEAR(s.volume(), 2.0 + 0.1875, 1e-12);  // cells aligned with the faces: exact

  CoveringReport report;
  const MlsOptions mls;
  const Eigen::VectorXd patches = cover_points(s.nodes, s.spacing, s.points, mls, {}, &report);
  EXPECT_LT(report.largest_growth, 1.5);
  std::printf("covering: %d of %d points repaired, %d nodes enlarged (up to %.2fx), %d passes; radii %.4f to %.4f\n",
              report.points_repaired, report.points, report.nodes_enlarged, report.largest_growth, report.passes,
              mls.support_factor * patches.minCoeff(), mls.support_factor * patches.maxCoeff());
  EXPECT_GE(patches.maxCoeff(), 3.9 * patches.minCoeff());  // mixed support radii
  for (const bool adaptive : {true, false}) {
    const PatchTest t = adaptive ? patch_test(s, patches, mls) : patch_test(uniform, uniform_patches, mls);
    std::printf("patch test, %s nodes: values %.1e, gradients %.1e, F %.1e; fewest covering nodes %d, largest "
                "condition %.1f\n",
                adaptive ? "adaptive" : "uniform (stretched supports)", t.worst_value, t.worst_gradient, t.worst_F,
                t.fewest, t.worst_condition);
    EXPECT_GE(t.fewest, 4);
    EXPECT_LE(t.worst_condition, 1e4);
    EXPECT_LT(t.worst_value, 1e-12);
    EXPECT_LT(t.worst_gradient, 1e-10);
    EXPECT_LT(t.worst_F, 1e-10);
  }
}

// A refinement box asks for finer nodes where the thin rule would not: the block's corner.
TEST(OctreeSampling, RefinementBoxSetsTheNodeLevel) {
  OctreeSamplingOptions options{0.25, 2, 0};
  options.max_level = 1;
  options.refine_thin = false;
  options.refine_boxes = {{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.5, 0.5, 0.5), 1}};
  const OctreeSampling s = sample_shape(box_shape(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1)), options);
  const OctreeSampling uniform = sample_shape(box_shape(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1)), {0.25, 2, 0});
  // The cells meeting the closed box [0, 0.5]^3 are the 3 x 3 x 3 root cells at the corner: their
  // 7^3 lattice of h / 2 adds 7^3 - 4^3 nodes to the uniform lattice.
  EXPECT_EQ(s.nodes.rows(), uniform.nodes.rows() + 7 * 7 * 7 - 4 * 4 * 4);
  EXPECT_EQ(s.cells_refined, 27);
  EXPECT_NEAR(s.volume(), 2.0, 1e-12);
  for (Eigen::Index a = 0; a < s.nodes.rows(); ++a)
    EXPECT_EQ(s.level[a], (s.nodes.row(a).array() <= 0.75 + 1e-9).all() ? 1 : 0) << s.nodes.row(a);
}

// neighbour_spacing against a brute-force search, and its values on a lattice: h inside, sqrt(2) h
// where the boundary leaves a node fewer than six neighbours at h.
TEST(CoveringPatches, NeighbourSpacingIsTheKthNearestNodesDistance) {
  const OctreeSampling lattice = sample_shape(box_shape(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 1)), {0.25, 2, 0});
  const Eigen::MatrixXd& X = lattice.nodes;
  const Eigen::VectorXd s = neighbour_spacing(X, 6);
  for (int a = 0; a < X.rows(); ++a) {
    const Eigen::Vector3d p = X.row(a).transpose();
    const bool interior = (p.array() > 1e-9).all() && (p.array() < Eigen::Array3d(2, 1, 1) - 1e-9).all();
    EXPECT_NEAR(s[a], interior ? 0.25 : 0.25 * std::sqrt(2.0), 1e-12) << a;
  }
  // Scattered points, clustered at one end: every k against sorting all distances.
  Eigen::MatrixXd P = Eigen::MatrixXd::Random(300, 3);
  P.col(0) = P.col(0).array().cube();
  for (const int k : {1, 4, 10}) {
    const Eigen::VectorXd fast = neighbour_spacing(P, k);
    for (int a = 0; a < P.rows(); ++a) {
      std::vector<double> d;
      for (int b = 0; b < P.rows(); ++b)
        if (b != a) d.push_back((P.row(b) - P.row(a)).norm());
      std::sort(d.begin(), d.end());
      ASSERT_DOUBLE_EQ(fast[a], d[static_cast<std::size_t>(k - 1)]) << "k = " << k << ", point " << a;
    }
  }
  EXPECT_THROW(neighbour_spacing(P, 0), std::invalid_argument);
  EXPECT_THROW(neighbour_spacing(P, 300), std::invalid_argument);
  // Any scale of the coordinates: the buckets are sized on ratios (at 1e-150 the box's volume
  // underflows; sized on it, a cell count overflowed an int, which the sanitizer build caught).
  const Eigen::VectorXd unit = neighbour_spacing(P, 3), tiny = neighbour_spacing(P * 1e-150, 3);
  EXPECT_NEAR(tiny[0] * 1e150, unit[0], 1e-12 * unit[0]);
  Eigen::MatrixXd twice(2, 3);
  twice << 0, 0, 0, 0, 0, 0;
  EXPECT_THROW(neighbour_spacing(twice, 1), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::sampling_test
