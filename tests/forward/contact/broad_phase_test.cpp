// The broad phase never misses a pair that brute force (all pairs, exact distances) finds.
#include "forward/contact/broad_phase.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace tailor::contact::broad_phase_test {
namespace {

// A soup of small random triangles in the unit cube.
ContactSurface triangle_soup(int triangles, std::mt19937& rng, Positions& x) {
  std::uniform_real_distribution<double> u(0.0, 1.0), w(-0.08, 0.08);
  x.resize(3 * triangles, 3);
  Eigen::MatrixX3i faces(triangles, 3);
  for (int f = 0; f < triangles; ++f) {
    const Eigen::RowVector3d c(u(rng), u(rng), u(rng));
    for (int k = 0; k < 3; ++k) {
      x.row(3 * f + k) = c + Eigen::RowVector3d(w(rng), w(rng), w(rng));
      faces(f, k) = 3 * f + k;
    }
  }
  return ContactSurface::from_faces(3 * triangles, faces);
}

template <class Pairs>
int missing(const Pairs& found, const Pairs& reference) {
  int count = 0;
  for (const auto& pair : reference)
    if (!std::binary_search(found.begin(), found.end(), pair)) ++count;
  return count;
}

TEST(ContactBroadPhase, NeverMissesAPairBruteForceFinds) {
  std::mt19937 rng(3);
  for (double d_hat : {0.01, 0.05, 0.2}) {
    Positions x;
    const ContactSurface surface = triangle_soup(150, rng, x);
    CandidatePairs reference = brute_force_pairs(surface, x, d_hat);
    const CandidatePairs found = find_candidates(surface, x, d_hat);
    ASSERT_GT(reference.size(), 0u);
    EXPECT_EQ(missing(found.point_triangle, reference.point_triangle), 0) << d_hat;
    EXPECT_EQ(missing(found.edge_edge, reference.edge_edge), 0) << d_hat;
    // ... and prunes: far fewer candidates than all pairs.
    const double all_pairs = 450.0 * 150.0 + 450.0 * 449.0 / 2.0;
    if (d_hat <= 0.05) {
      EXPECT_LT(static_cast<double>(found.size()), 0.2 * all_pairs);
    }
  }
}

TEST(ContactBroadPhase, SweptBoxesCoverEveryPairTheMotionBringsClose) {
  std::mt19937 rng(5);
  Positions x;
  const ContactSurface surface = triangle_soup(100, rng, x);
  std::uniform_real_distribution<double> w(-0.1, 0.1);
  Positions end = x;
  for (int v = 0; v < x.rows(); ++v) end.row(v) += Eigen::RowVector3d(w(rng), w(rng), w(rng));
  const CandidatePairs found = find_candidates(surface, x, 0.0, &end);
  // Every pair close at some sampled time of the straight motion is a candidate.
  for (double t : {0.0, 0.25, 0.5, 0.75, 1.0}) {
    const Positions xt = x + t * (end - x);
    const CandidatePairs close = brute_force_pairs(surface, xt, 1e-3);
    EXPECT_EQ(missing(found.point_triangle, close.point_triangle), 0) << t;
    EXPECT_EQ(missing(found.edge_edge, close.edge_edge), 0) << t;
  }
}

TEST(ContactBroadPhase, SkipsAdjacentAndSameGroupPairs) {
  // Two triangles sharing an edge: no vertex-own-face or shared-vertex edge pairs.
  Positions x(4, 3);
  x << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0;
  Eigen::MatrixX3i faces(2, 3);
  faces << 0, 1, 2, 1, 3, 2;
  const ContactSurface surface = ContactSurface::from_faces(4, faces);
  const CandidatePairs pairs = find_candidates(surface, x, 10.0);
  for (const auto& [v, f] : pairs.point_triangle) EXPECT_TRUE(admissible_point_triangle(surface, v, f));
  EXPECT_EQ(pairs.point_triangle.size(), 2u);  // 0 with face 1, 3 with face 0
  const ContactSurface grouped = ContactSurface::from_faces(4, faces, {0, 0, 0, 0});
  EXPECT_EQ(find_candidates(grouped, x, 10.0).size(), 0u);
  EXPECT_THROW(ContactSurface::from_faces(3, faces), std::invalid_argument);
  EXPECT_THROW(find_candidates(surface, Positions(3, 3), 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::contact::broad_phase_test
