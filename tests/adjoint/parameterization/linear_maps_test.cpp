// linear_basis_map, region_scatter_map, spline_map: maps linear in z.
#include <chrono>

#include "map_checks.hpp"

namespace tailor::linear_maps_test {
namespace {

using testing::random_vector;

TEST(LinearBasisMap, IsBasisTimesZPlusOffset) {
  const Matrix basis = Matrix::Random(7, 3);
  const Vector offset = random_vector(7, 1);
  const auto map = linear_basis_map(basis, offset);
  EXPECT_EQ(map->name(), "linear_basis(3 -> 7)");
  const Vector z = random_vector(3, 2);
  EXPECT_TRUE(map->apply(z).isApprox(basis * z + offset, 1e-15));
  EXPECT_TRUE(map->jacobian(z).isApprox(basis, 1e-15));
  testing::expect_first_order_consistent(*map, z, false);
  testing::expect_linear_in_z(*map, z);
}

TEST(RegionScatterMap, GathersForwardAndSumsBackward) {
  const std::vector<int> region{2, 0, 0, 1, 2, 2, 0, 1, 2};  // region 3 has no entries
  const auto map = region_scatter_map(region, 4);
  EXPECT_EQ(map->name(), "region_scatter(4 -> 9)");
  const Vector z = (Vector(4) << 10.0, 20.0, 30.0, 40.0).finished();
  const Vector p = map->apply(z);
  for (int e = 0; e < 9; ++e) EXPECT_EQ(p[e], z[region[e]]);
  const Vector w = Vector::LinSpaced(9, 1.0, 9.0);  // entry e carries weight e + 1
  const Vector expected = (Vector(4) << 2 + 3 + 7, 4 + 8, 1 + 5 + 6 + 9, 0).finished();
  EXPECT_EQ(map->jacobian_transpose_times(z, w), expected);
  testing::expect_first_order_consistent(*map, z, false);
  testing::expect_linear_in_z(*map, z);
}

TEST(RegionScatterMap, MillionEntriesInLinearTime) {
  // A dense Jacobian here would be 1e6 x 1e3 doubles (8 GB): the products must not form one.
  const int entries = 1'000'000, regions = 1000;
  std::vector<int> region(entries);
  for (int e = 0; e < entries; ++e) region[e] = static_cast<int>((7919LL * e) % regions);
  const auto map = compose(
      exp_map(entries),
      compose(region_scatter_map(region, regions), bounds_map(Vector::Zero(regions), Vector::Ones(regions))));
  const Vector z = random_vector(regions, 3);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_LT(testing::dot_product_mismatch(*map, z), 1e-12);
  const Vector second = map->second_derivative_times(z, random_vector(entries, 4), random_vector(regions, 5));
  EXPECT_EQ(second.size(), regions);
  // Generous: the products take milliseconds; anything quadratic would take far longer.
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 20.0);
}

TEST(SplineMap, InterpolatesControlValuesAtKnots) {
  const Vector knots = (Vector(6) << -1.0, 0.0, 0.5, 2.0, 2.1, 4.0).finished();
  const auto map = spline_map(knots, knots);
  EXPECT_EQ(map->name(), "spline(6 knots -> 6 samples)");
  const Vector z = random_vector(6, 1);
  EXPECT_TRUE(map->apply(z).isApprox(z, 1e-14)) << map->apply(z).transpose();
}

TEST(SplineMap, ReproducesLinearFunctionsIncludingExtrapolation) {
  const Vector knots = (Vector(5) << 0.0, 0.3, 1.0, 1.2, 3.0).finished();
  const Vector samples = Vector::LinSpaced(41, -2.0, 5.0);
  const auto map = spline_map(knots, samples);
  const Vector z = (2.0 - 1.5 * knots.array()).matrix();
  const Vector expected = (2.0 - 1.5 * samples.array()).matrix();
  EXPECT_LT((map->apply(z) - expected).lpNorm<Eigen::Infinity>(), 1e-13);
}

TEST(SplineMap, MatchesHandComputedThreeKnotSpline) {
  // Knots 0, 1, 3 with values 0, 1, 0. The interior equation 1*M0 + 2(1+2) M1 + 2*M2 =
  // 6((0-1)/2 - (1-0)/1) with M0 = M2 = 0 gives M1 = -3/2, so
  //   s(x) = 1.25 x - 0.25 x^3                                  on [0, 1],
  //   s(x) = 1 + 0.5 u - 0.75 u^2 + 0.125 u^3, u = x - 1        on [1, 3],
  // with end slopes s'(0) = 1.25 and s'(3) = -1 for the linear extrapolation.
  const Vector knots = (Vector(3) << 0.0, 1.0, 3.0).finished();
  const Vector samples = (Vector(5) << -2.0, 0.5, 1.0, 2.0, 4.0).finished();
  const auto map = spline_map(knots, samples);
  const Vector p = map->apply((Vector(3) << 0.0, 1.0, 0.0).finished());
  const Vector expected = (Vector(5) << -2.5, 0.59375, 1.0, 0.875, -1.0).finished();
  EXPECT_LT((p - expected).lpNorm<Eigen::Infinity>(), 1e-14) << p.transpose();
}

TEST(SplineMap, TwoKnotsGiveTheStraightLine) {
  const auto map = spline_map((Vector(2) << 1.0, 3.0).finished(), (Vector(3) << 0.0, 2.0, 4.0).finished());
  const Vector p = map->apply((Vector(2) << 1.0, 5.0).finished());
  EXPECT_LT((p - (Vector(3) << -1.0, 3.0, 7.0).finished()).lpNorm<Eigen::Infinity>(), 1e-14);
}

TEST(SplineMap, IsTwiceContinuouslyDifferentiableAndNatural) {
  // One-sided difference quotients on either side of each knot: first and second derivatives
  // agree across interior knots (what the tridiagonal system enforces), and s'' = 0 at the
  // ends, where the linear extension takes over. Errors are O(h) s''' plus round-off.
  const Vector knots = (Vector(6) << -1.0, 0.0, 0.5, 2.0, 2.6, 4.0).finished();
  const Vector z = random_vector(6, 9);
  const double h = 1e-5;
  for (int k = 0; k < 6; ++k) {
    const Vector samples = (Vector(5) << -2 * h, -h, 0.0, h, 2 * h).finished().array() + knots[k];
    const Vector s = spline_map(knots, samples)->apply(z);
    const double left_slope = (s[2] - s[1]) / h, right_slope = (s[3] - s[2]) / h;
    const double left_curvature = (s[0] - 2 * s[1] + s[2]) / (h * h);
    const double right_curvature = (s[2] - 2 * s[3] + s[4]) / (h * h);
    EXPECT_NEAR(left_slope, right_slope, 1e-3) << "knot " << k;
    EXPECT_NEAR(left_curvature, right_curvature, 1e-2) << "knot " << k;
    if (k == 0 || k == 5) {
      EXPECT_NEAR(left_curvature, 0.0, 1e-2) << "knot " << k;
    }
  }
}

TEST(SplineMap, DerivativesAreTheWeightMatrix) {
  const Vector knots = (Vector(5) << 0.0, 0.3, 1.0, 1.2, 3.0).finished();
  const auto map = spline_map(knots, Vector::LinSpaced(30, -0.5, 3.5));
  const Vector z = random_vector(5, 2);
  testing::expect_first_order_consistent(*map, z, false);
  testing::expect_linear_in_z(*map, z);
  // Linear: apply(z) = J z exactly (no offset).
  EXPECT_TRUE(map->apply(z).isApprox(map->jacobian(z) * z, 1e-14));
}

}  // namespace
}  // namespace tailor::linear_maps_test
