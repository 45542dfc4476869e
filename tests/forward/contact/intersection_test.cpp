// Segment-triangle crossings (the validation check after each step): known cases, and a
// piercing edge that every point-triangle and edge-edge distance misses.
#include "forward/contact/intersection.hpp"

#include <gtest/gtest.h>

namespace tailor::contact::intersection_test {
namespace {

TEST(ContactIntersection, SegmentTriangleKnownCases) {
  const Point t0(0, 0, 0), t1(1, 0, 0), t2(0, 1, 0);
  EXPECT_TRUE(segment_intersects_triangle(Point(.2, .2, 1), Point(.2, .2, -1), t0, t1, t2));
  EXPECT_FALSE(segment_intersects_triangle(Point(.2, .2, 1), Point(.2, .2, 0.1), t0, t1, t2));
  EXPECT_FALSE(segment_intersects_triangle(Point(.8, .8, 1), Point(.8, .8, -1), t0, t1, t2));
  EXPECT_TRUE(segment_intersects_triangle(Point(.5, 0, 1), Point(.5, 0, -1), t0, t1, t2));  // through an edge
  EXPECT_TRUE(
      segment_intersects_triangle(Point(.2, .2, 0), Point(.2, .2, -1), t0, t1, t2));  // endpoint on face
}

TEST(ContactIntersection, PiercingEdgeIsFoundWhereDistancesAreAllPositive) {
  // A big floor triangle and a small triangle standing through its interior.
  Positions x(6, 3);
  x << -2, -2, 0, 4, -2, 0, -2, 4, 0,  //
      0, 0, -0.5, 0.3, 0, 0.5, 0, 0.3, 0.5;
  Eigen::MatrixX3i faces(2, 3);
  faces << 0, 1, 2, 3, 4, 5;
  const ContactSurface surface = ContactSurface::from_faces(6, faces);
  const CandidatePairs all = brute_force_pairs(surface, x, 1e9);
  for (const auto& [v, f] : all.point_triangle) {
    const auto t = surface.faces.row(f);
    EXPECT_GT(classify_point_triangle(x.row(v).transpose(), x.row(t[0]).transpose(), x.row(t[1]).transpose(),
                                      x.row(t[2]).transpose())
                  .squared_distance,
              0.0);
  }
  EXPECT_EQ(count_edge_face_intersections(surface, x), 2);  // two edges of the small triangle pierce
}

}  // namespace
}  // namespace tailor::contact::intersection_test
