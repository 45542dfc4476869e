// Elliptic-tube torus distance: closed-form stacked and side-by-side pairs, random pairs against
// a dense-sampling reference (distance and overlap), agreement with the circular core-circle
// formula when r1 = r, and derivative checks of the implicit-function-theorem gradient and
// Hessian against central differences (with a dropped IFT term that the same check rejects).
#include "forward/tori/elliptic_distance.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "forward/rigid/rotation.hpp"

namespace tailor::tori::elliptic_distance_test {
namespace {

TorusShape elliptic(double R, double r, double r1) { return {R, r, r1}; }

TEST(EllipticTorusDistance, StackedParallelAxesMatchTheClosedForm) {
  // Closed form: axes parallel (both along z), b above a by dz, axes 0.76 apart so that a's top
  // ridge (radius R_a at height r1_a) and b's bottom ridge (radius R_b at dz - r1_b) cross in
  // projection: every point of a lies at z <= r1_a and of b at z >= dz - r1_b, and the crossing
  // points attain it, so d = dz - r1_a - r1_b whatever R, r.
  const TorusPose a{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), elliptic(1.0, 0.2, 0.35)};
  const TorusPose b{Eigen::Vector3d(0.7, 0.3, 0.6), Eigen::Vector3d(0, 0, 0.4), elliptic(0.9, 0.25, 0.15)};
  const TorusDistance d = torus_distance(a, b, true);
  EXPECT_NEAR(d.distance, 0.6 - 0.35 - 0.15, 1e-12);
  EXPECT_FALSE(d.degenerate);
  EXPECT_FALSE(d.overlapping);
  EXPECT_TRUE(std::isnan(d.core_distance));
  EXPECT_NEAR(d.gradient[8], 1.0, 1e-9);   // raising b opens the gap
  EXPECT_NEAR(d.gradient[2], -1.0, 1e-9);  // raising a closes it
  for (int i : {0, 1, 6, 7, 12, 13, 14, 15}) EXPECT_NEAR(d.gradient[i], 0.0, 1e-9) << i;
  EXPECT_NEAR(d.axial_gradient[0], -1.0, 1e-9);
  EXPECT_NEAR(d.axial_gradient[1], -1.0, 1e-9);
  // Coaxial, the same closed form holds on a whole circle of minimizers: the value is right,
  // the pair is reported degenerate (no derivatives).
  const TorusPose c{Eigen::Vector3d(0, 0, 0.6), Eigen::Vector3d(0, 0, 0.4), elliptic(1.0, 0.25, 0.15)};
  const TorusDistance coaxial = torus_distance(a, c, true);
  EXPECT_NEAR(coaxial.distance, 0.1, 1e-10);
  EXPECT_TRUE(coaxial.degenerate);
}

TEST(EllipticTorusDistance, CoplanarSideBySideMatchTheClosedForm) {
  // Closed form: both in the plane z = 0, centres c apart; every point of a is within R_a + r_a
  // of a's axis, of b within R_b + r_b of b's, and the outer equators on the line of centres
  // attain it: d = c - R_a - r_a - R_b - r_b whatever r1.
  const TorusPose a{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), elliptic(1.0, 0.2, 0.35)};
  const TorusPose b{Eigen::Vector3d(2.45, 0, 0), Eigen::Vector3d(0, 0, 1.1), elliptic(0.9, 0.25, 0.15)};
  const TorusDistance d = torus_distance(a, b, true);
  EXPECT_NEAR(d.distance, 0.1, 1e-12);
  EXPECT_FALSE(d.degenerate);
  EXPECT_NEAR(d.gradient[6], 1.0, 1e-9);
  for (int i : {12, 13, 14, 15}) EXPECT_NEAR(d.gradient[i], -1.0, 1e-9) << i;
  EXPECT_NEAR(d.axial_gradient.norm(), 0.0, 1e-9);
}

// Reference: the distance from x to b's surface. The nearest point of a surface of revolution
// lies in x's meridian half-plane, so it is the distance of (rho, z) to b's section ellipse
// (R + r cos v, r1 sin v): 128 samples of v, then golden-section search about the best.
double point_surface_distance(const TorusPose& b, const Eigen::Vector3d& x) {
  const Eigen::Vector3d y = rigid::rotation_matrix(b.rotation).transpose() * (x - b.position);
  const double rho = std::hypot(y[0], y[1]), z = y[2];
  const double R = b.shape.major_radius, r = b.shape.minor_radius, r1 = axial_radius(b.shape);
  auto h = [&](double v) { return std::hypot(rho - R - r * std::cos(v), z - r1 * std::sin(v)); };
  const int n = 128;
  int best = 0;
  for (int k = 1; k < n; ++k)
    if (h(2 * M_PI * k / n) < h(2 * M_PI * best / n)) best = k;
  double lo = 2 * M_PI * (best - 1) / n, hi = 2 * M_PI * (best + 1) / n;
  const double phi = (std::sqrt(5.0) - 1.0) / 2.0;
  for (int it = 0; it < 80; ++it) {
    const double m1 = hi - phi * (hi - lo), m2 = lo + phi * (hi - lo);
    if (h(m1) < h(m2))
      hi = m2;
    else
      lo = m1;
  }
  return h(0.5 * (lo + hi));
}

// Reference distance of two disjoint tori: a's surface sampled on a 160 x 80 grid, then three
// times a 21 x 21 grid over the two cells around the best sample, each 10 times finer, each
// sample's exact distance to b. Only an upper bound (by the sampling of a, here ~1e-9).
double sampled_distance(const TorusPose& a, const TorusPose& b) {
  const int nu = 160, nv = 80;
  double best = std::numeric_limits<double>::infinity(), bu = 0, bv = 0;
  auto sample = [&](double u, double v) {
    const double d = point_surface_distance(b, surface_point(a, u, v));
    if (d < best) {
      best = d;
      bu = u;
      bv = v;
    }
  };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) sample(2 * M_PI * i / nu, 2 * M_PI * j / nv);
  double du = 2 * M_PI / nu, dv = 2 * M_PI / nv;
  for (int level = 0; level < 3; ++level) {
    const double cu = bu, cv = bv;
    for (int i = -10; i <= 10; ++i)
      for (int j = -10; j <= 10; ++j) sample(cu + du * i / 10.0, cv + dv * j / 10.0);
    du /= 10.0;
    dv /= 10.0;
  }
  return best;
}

// Overlap by dense sampling: some sample of one surface inside the other solid.
bool sampled_overlap(const TorusPose& a, const TorusPose& b) {
  const int nu = 240, nv = 120;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nv;
      if (implicit_value(b, surface_point(a, u, v)) < 0.0 || implicit_value(a, surface_point(b, u, v)) < 0.0)
        return true;
    }
  return false;
}

TEST(EllipticTorusDistance, RandomPairsAgreeWithDenseSamplingInDistanceAndOverlap) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0), p(0.0, 1.0);
  int apart = 0, overlapping = 0;
  double worst = 0.0;
  for (int k = 0; k < 30; ++k) {
    const TorusPose a{Eigen::Vector3d::Zero(), Eigen::Vector3d(u(rng), u(rng), u(rng)) * 2.0,
                      elliptic(1.0, 0.1 + 0.2 * p(rng), 0.1 + 0.35 * p(rng))};
    const TorusPose b{Eigen::Vector3d(u(rng), u(rng), u(rng)) * 1.6,
                      Eigen::Vector3d(u(rng), u(rng), u(rng)) * 2.0,
                      elliptic(0.7 + 0.4 * p(rng), 0.1 + 0.2 * p(rng), 0.1 + 0.35 * p(rng))};
    const TorusDistance d = torus_distance(a, b, false);
    EXPECT_EQ(d.overlapping, sampled_overlap(a, b)) << k;
    if (d.overlapping) {
      EXPECT_LT(d.distance, 0.0) << k;
      ++overlapping;
      continue;
    }
    const double reference = sampled_distance(a, b);
    // Ours is attained at actual surface points (never below the truth); the reference is the
    // truth up to its sampling; a missed global minimum would put ours above the reference.
    EXPECT_LE(d.distance, reference + 1e-12) << k;
    EXPECT_GE(d.distance, reference - 1e-8) << k;
    worst = std::max(worst, std::abs(d.distance - reference));
    ++apart;
  }
  std::printf("random elliptic pairs: %d apart (largest difference to the reference %.1e), %d overlapping\n",
              apart, worst, overlapping);
  EXPECT_GE(apart, 8);
  EXPECT_GE(overlapping, 5);
}

TEST(EllipticTorusDistance, ASymmetricSaddleIsLeftForTheTrueMinimum) {
  // Hanging links with a wide tube (r1 = 0.41 > sqrt(r (R - r)) = 0.4): the inner equators'
  // contact on the axis is a saddle of f with zero gradient by symmetry (d = 2R - s - 2r = 1e-3
  // there); the closest points lie off the axis, closer. Reference: dense sampling.
  const TorusPose a{Eigen::Vector3d::Zero(), Eigen::Vector3d(M_PI / 2, 0, 0), elliptic(1.0, 0.2, 0.41)};
  const TorusPose b{Eigen::Vector3d(0, 0, -1.599), Eigen::Vector3d(0, M_PI / 2, 0), elliptic(1.0, 0.2, 0.41)};
  const TorusDistance d = torus_distance(a, b, false);
  const double reference = sampled_distance(a, b);
  EXPECT_LT(reference, 0.9e-3);
  EXPECT_LE(d.distance, reference + 1e-12);
  EXPECT_GE(d.distance, reference - 1e-8);
}

TEST(EllipticTorusDistance, ATorusInsideAnothersTubeOverlaps) {
  // The surfaces are apart but b lies inside a's solid tube: found by g_a on b's surface.
  const TorusPose a{Eigen::Vector3d::Zero(), Eigen::Vector3d(0.2, 0, 0), elliptic(1.0, 0.4, 0.5)};
  const TorusPose b{rigid::rotation_matrix(a.rotation) * Eigen::Vector3d(1, 0, 0),
                    Eigen::Vector3d(0.5, -1.0, 0.3), elliptic(0.15, 0.05, 0.08)};
  const TorusDistance d = torus_distance(a, b, true);
  EXPECT_TRUE(d.overlapping);
  EXPECT_TRUE(d.degenerate);
  EXPECT_LT(d.distance, 0.0);
  EXPECT_TRUE(sampled_overlap(a, b));
}

// The 16 pair variables and r1 of both as one vector, and back.
using Variables = Eigen::Matrix<double, 18, 1>;
Variables variables_of(const TorusPose& a, const TorusPose& b) {
  Variables x;
  x << a.position, a.rotation, b.position, b.rotation, a.shape.major_radius, a.shape.minor_radius,
      b.shape.major_radius, b.shape.minor_radius, axial_radius(a.shape), axial_radius(b.shape);
  return x;
}
std::pair<TorusPose, TorusPose> poses_of(const Variables& x, bool circular_a, bool circular_b) {
  TorusPose a{x.segment<3>(0), x.segment<3>(3), {x[12], x[13], circular_a ? 0.0 : x[16]}};
  TorusPose b{x.segment<3>(6), x.segment<3>(9), {x[14], x[15], circular_b ? 0.0 : x[17]}};
  return {a, b};
}

struct DerivativeErrors {
  double gradient, hessian, axial;
};

// Central differences of d (gradient, r1 gradient, step 1e-6) and of the analytic gradient
// (Hessian, step 1e-5) against the analytic ones; relative errors in the max norm.
DerivativeErrors derivative_errors(const TorusPose& a, const TorusPose& b, const DistanceOptions& options) {
  const bool ca = !is_elliptic(a.shape), cb = !is_elliptic(b.shape);
  const Variables x = variables_of(a, b);
  const TorusDistance d = torus_distance(a, b, true, options);
  EXPECT_FALSE(d.degenerate);
  auto at = [&](const Variables& y) {
    const auto [pa, pb] = poses_of(y, ca, cb);
    return torus_distance(pa, pb, true, options);
  };
  PairGradient g_fd;
  PairHessian h_fd;
  Eigen::Vector2d axial_fd = Eigen::Vector2d::Zero();
  for (int i = 0; i < 18; ++i) {
    if ((i == 16 && ca) || (i == 17 && cb)) continue;
    Variables e = Variables::Zero();
    e[i] = 1e-6;
    const double fd = (at(x + e).distance - at(x - e).distance) / 2e-6;
    if (i >= 16) {
      axial_fd[i - 16] = fd;
    } else {
      g_fd[i] = fd;
      e[i] = 1e-5;
      h_fd.col(i) = (at(x + e).gradient - at(x - e).gradient) / 2e-5;
    }
  }
  DerivativeErrors out;
  out.gradient = (g_fd - d.gradient).lpNorm<Eigen::Infinity>() / d.gradient.lpNorm<Eigen::Infinity>();
  out.hessian = (h_fd - d.hessian).lpNorm<Eigen::Infinity>() / d.hessian.lpNorm<Eigen::Infinity>();
  out.axial = (axial_fd - d.axial_gradient).lpNorm<Eigen::Infinity>();
  return out;
}

std::vector<std::pair<TorusPose, TorusPose>> generic_pairs() {
  // Interlocked links (a chain's pair, twisted), a skew stacked pair and a skew side-by-side
  // pair of an elliptic and a circular torus (whose r moves both its semi-axes).
  return {{{Eigen::Vector3d::Zero(), Eigen::Vector3d(M_PI / 2 - 0.02, 0.03, 0.01), elliptic(1.0, 0.2, 0.3)},
           {Eigen::Vector3d(0.03, -0.02, -1.58), Eigen::Vector3d(0.05, M_PI / 2 - 0.04, 0.07),
            elliptic(1.0, 0.2, 0.3)}},
          {{Eigen::Vector3d::Zero(), Eigen::Vector3d(0.1, -0.2, 0.3), elliptic(1.0, 0.2, 0.35)},
           {Eigen::Vector3d(0.6, 0.2, 0.95), Eigen::Vector3d(-0.3, 0.25, 1.0), elliptic(0.9, 0.25, 0.15)}},
          {{Eigen::Vector3d::Zero(), Eigen::Vector3d(0.3, 0.1, -0.2), elliptic(1.0, 0.3, 0.15)},
           {Eigen::Vector3d(2.4, 0.3, 0.1), Eigen::Vector3d(0.4, 0.2, -0.5), TorusShape{0.8, 0.2}}}};
}

TEST(EllipticTorusDistance, GradientAndHessianPassCentralDifferences) {
  for (const auto& [a, b] : generic_pairs()) {
    const TorusDistance d = torus_distance(a, b, false);
    ASSERT_GT(d.distance, 0.0);
    const DerivativeErrors e = derivative_errors(a, b, {});
    std::printf("d = %.4f: gradient %.2e, Hessian %.2e, r1 gradient %.2e\n", d.distance, e.gradient,
                e.hessian, e.axial);
    EXPECT_LT(e.gradient, 1e-7);
    EXPECT_LT(e.hessian, 1e-5);
    EXPECT_LT(e.axial, 1e-7);
  }
}

TEST(EllipticTorusDistance, DerivativeCheckRejectsAMissingImplicitCorrection) {
  // The Hessian without -f_yu f_uu^-1 f_uy (the surface points held) must fail the same check
  // while the gradient still passes.
  DistanceOptions wrong;
  wrong.implicit_correction = false;
  for (const auto& [a, b] : generic_pairs()) {
    const DerivativeErrors e = derivative_errors(a, b, wrong);
    std::printf("without the IFT term: gradient %.2e, Hessian %.2e\n", e.gradient, e.hessian);
    EXPECT_LT(e.gradient, 1e-7);
    EXPECT_GT(e.hessian, 1e-2);
  }
}

TEST(EllipticTorusDistance, CircularTubesAgreeWithTheCoreCircleFormula) {
  // r1 = r: the surface minimization against d = D - r_a - r_b of torus_distance.hpp, value,
  // gradient and Hessian (whose r rows vanish: d is linear in r there).
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<std::pair<TorusPose, TorusPose>> pairs = {
      {{Eigen::Vector3d::Zero(), Eigen::Vector3d(M_PI / 2 - 0.02, 0.03, 0.01), TorusShape{1.0, 0.2}},
       {Eigen::Vector3d(0.03, -0.02, -1.59), Eigen::Vector3d(0.05, M_PI / 2 - 0.04, 0.07),
        TorusShape{1.0, 0.2}}}};
  while (pairs.size() < 8) {
    const TorusPose a{Eigen::Vector3d::Zero(), Eigen::Vector3d(u(rng), u(rng), u(rng)) * 2.0,
                      TorusShape{1.0, 0.2}};
    const TorusPose b{Eigen::Vector3d(u(rng), u(rng), u(rng)) * 1.8,
                      Eigen::Vector3d(u(rng), u(rng), u(rng)) * 2.0, TorusShape{0.9, 0.15}};
    const TorusDistance d = torus_distance(a, b, false);
    if (d.distance > 0.02 && !d.degenerate) pairs.push_back({a, b});
  }
  for (const auto& [a, b] : pairs) {
    const TorusDistance circular = torus_distance(a, b, true), surface = elliptic_torus_distance(a, b, true);
    ASSERT_FALSE(surface.degenerate);
    EXPECT_NEAR(surface.distance, circular.distance, 1e-10);
    EXPECT_LT((surface.gradient - circular.gradient).lpNorm<Eigen::Infinity>(), 1e-9);
    EXPECT_LT((surface.hessian - circular.hessian).lpNorm<Eigen::Infinity>(),
              1e-7 * circular.hessian.lpNorm<Eigen::Infinity>());
    // An explicit r1 = r is the circular path, bit for bit.
    TorusPose a1 = a, b1 = b;
    a1.shape.minor_radius_1 = a.shape.minor_radius;
    b1.shape.minor_radius_1 = b.shape.minor_radius;
    const TorusDistance same = torus_distance(a1, b1, true);
    EXPECT_EQ(same.distance, circular.distance);
    EXPECT_EQ(same.gradient, circular.gradient);
    EXPECT_EQ(same.hessian, circular.hessian);
  }
}

}  // namespace
}  // namespace tailor::tori::elliptic_distance_test
