// Additive CCD on hard queries with known answers (the references are the closed-form times
// of impact of these constructed motions): false negatives must be 0; false positives (a
// step shortened although nothing touches in [0, 1]) are counted and reported.
#include "forward/contact/additive_ccd.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "forward/contact/contact_potential.hpp"

namespace tailor::contact::additive_ccd_test {
namespace {

struct Query {
  const char* name;
  PairKind kind;
  std::array<Point, 4> start, end;
  double time_of_impact;  // first contact in [0, 1], or > 1 when none
};

Point P(double x, double y, double z) { return Point(x, y, z); }
std::array<Point, 4> shift(std::array<Point, 4> s, const Point& d) {
  for (Point& p : s) p += d;
  return s;
}

std::vector<Query> hard_queries() {
  const Point t0 = P(0, 0, 0), t1 = P(1, 0, 0), t2 = P(0, 1, 0);
  const auto PT = PairKind::point_triangle;
  const auto EE = PairKind::edge_edge;
  const Point a0 = P(0, 0, 0), a1 = P(1, 0, 0);
  const double none = 2.0, g = 1e-8;
  std::vector<Query> q = {
      {"vertex reaches face exactly at t=1", PT, {P(.2, .2, 1), t0, t1, t2}, {P(.2, .2, 0), t0, t1, t2}, 1.0},
      {"vertex passes through face", PT, {P(.2, .2, 1), t0, t1, t2}, {P(.2, .2, -1), t0, t1, t2}, 0.5},
      {"vertex stops 1e-8 above face", PT, {P(.2, .2, 1), t0, t1, t2}, {P(.2, .2, g), t0, t1, t2}, none},
      {"vertex starts 1e-8 above, crosses", PT, {P(.2, .2, g), t0, t1, t2}, {P(.2, .2, -g), t0, t1, t2}, 0.5},
      {"vertex starts 1e-8 above, leaves", PT, {P(.2, .2, g), t0, t1, t2}, {P(.2, .2, 1), t0, t1, t2}, none},
      {"vertex misses edge by 1e-8", PT, {P(.5, -g, 1), t0, t1, t2}, {P(.5, -g, -1), t0, t1, t2}, none},
      {"vertex hits edge exactly", PT, {P(.5, 0, 1), t0, t1, t2}, {P(.5, 0, -1), t0, t1, t2}, 0.5},
      {"vertex hits corner exactly", PT, {P(0, 0, 1), t0, t1, t2}, {P(0, 0, -1), t0, t1, t2}, 0.5},
      {"zero-length motion at 1e-8", PT, {P(.2, .2, g), t0, t1, t2}, {P(.2, .2, g), t0, t1, t2}, none},
      {"common translation at 1e-8",
       PT,
       {P(.2, .2, g), t0, t1, t2},
       shift({P(.2, .2, g), t0, t1, t2}, P(3, -2, 5)),
       none},
      {"face moves onto resting vertex",
       PT,
       {P(.2, .2, 0), P(0, 0, 1), P(1, 0, 1), P(0, 1, 1)},
       {P(.2, .2, 0), P(0, 0, -1), P(1, 0, -1), P(0, 1, -1)},
       0.5},
      {"degenerate (collinear) face hit",
       PT,
       {P(.5, 1, 0), t0, t1, P(2, 0, 0)},
       {P(.5, -1, 0), t0, t1, P(2, 0, 0)},
       0.5},
      {"vertex slides 1e-8 above face", PT, {P(.1, .2, g), t0, t1, t2}, {P(.4, .3, g), t0, t1, t2}, none},
      {"far from origin, gap 1e-8 at t=1", PT, shift({P(.2, .2, 1), t0, t1, t2}, P(1e3, 1e3, 1e3)),
       shift({P(.2, .2, g), t0, t1, t2}, P(1e3, 1e3, 1e3)), none},
      {"parallel edges meet at t=1",
       EE,
       {a0, a1, P(0, 0, 1), P(1, 0, 1)},
       {a0, a1, P(.3, 0, 0), P(1.3, 0, 0)},
       1.0},
      {"parallel edges stop 1e-8 apart",
       EE,
       {a0, a1, P(0, 0, 1), P(1, 0, 1)},
       {a0, a1, P(0, 0, g), P(1, 0, g)},
       none},
      {"parallel edges slide 1e-8 apart",
       EE,
       {a0, a1, P(-.5, 0, g), P(.5, 0, g)},
       {a0, a1, P(.5, 0, g), P(1.5, 0, g)},
       none},
      {"crossing edges pass through",
       EE,
       {a0, a1, P(.5, -1, 1), P(.5, 1, 1)},
       {a0, a1, P(.5, -1, -1), P(.5, 1, -1)},
       0.5},
      {"edge endpoints touch at t=1",
       EE,
       {a0, a1, P(1, 0, 1), P(1, 1, 1)},
       {a0, a1, P(1, 0, 0), P(1, 1, 0)},
       1.0},
      {"edges miss by 1e-8 past an end",
       EE,
       {a0, a1, P(1 + g, -1, 1), P(1 + g, 1, 1)},
       {a0, a1, P(1 + g, -1, -1), P(1 + g, 1, -1)},
       none},
      {"nearly parallel edges (1e-8 rad) cross",
       EE,
       {a0, a1, P(0, g, 1), P(1, -g, 1)},
       {a0, a1, P(0, g, -1), P(1, -g, -1)},
       0.5},
      {"zero-length motion edges at 1e-8",
       EE,
       {a0, a1, P(.5, -1, g), P(.5, 1, g)},
       {a0, a1, P(.5, -1, g), P(.5, 1, g)},
       none},
      {"edge tilts down onto edge",
       EE,
       {a0, a1, P(.5, -1, 1), P(.5, 1, 2)},
       {a0, a1, P(.5, -1, -1), P(.5, 1, 0)},
       0.75},
  };
  return q;
}

TEST(AdditiveCcd, HardQueriesHaveNoFalseNegatives) {
  int false_negatives = 0, false_positives = 0, colliding = 0;
  std::printf("%-42s %8s %12s\n", "query", "impact", "ACCD step");
  for (const Query& q : hard_queries()) {
    const double step = additive_ccd_linear(q.kind, q.start, q.end);
    const bool collides = q.time_of_impact <= 1.0;
    std::printf("%-42s %8.3g %12.6g\n", q.name, collides ? q.time_of_impact : NAN, step);
    EXPECT_GE(step, 0.0);
    EXPECT_LE(step, 1.0);
    if (collides) {
      ++colliding;
      if (step >= q.time_of_impact) {
        ++false_negatives;
        ADD_FAILURE() << "false negative: " << q.name;
      }
    } else if (step < 1.0) {
      ++false_positives;
    }
  }
  std::printf("queries %zu, colliding %d, false negatives %d, false positives %d\n", hard_queries().size(),
              colliding, false_negatives, false_positives);
  EXPECT_EQ(false_negatives, 0);
}

TEST(AdditiveCcd, StepKeepsAFractionOfTheGapAndExactAnswersWhereNoMotion) {
  for (const Query& q : hard_queries()) {
    const double step = additive_ccd_linear(q.kind, q.start, q.end);
    if (step >= 1.0) continue;
    std::array<Point, 4> at;
    for (int k = 0; k < 4; ++k) at[k] = q.start[k] + step * (q.end[k] - q.start[k]);
    // The returned step leaves at least s = 0.1 of the initial distance (up to round-off).
    EXPECT_GE(pair_distance(q.kind, at), 0.1 * pair_distance(q.kind, q.start) * (1 - 1e-6)) << q.name;
  }
  const Point t0(0, 0, 0), t1(1, 0, 0), t2(0, 1, 0);
  const std::array<Point, 4> rest{Point(.2, .2, 1e-8), t0, t1, t2};
  EXPECT_EQ(additive_ccd_linear(PairKind::point_triangle, rest, rest), 1.0);
  // A pair that starts in contact admits no step.
  const std::array<Point, 4> touching{Point(.2, .2, 0), t0, t1, t2};
  EXPECT_EQ(additive_ccd_linear(PairKind::point_triangle, touching, rest), 0.0);
}


// A NaN or infinite motion is refused at once (step 0, status non_finite) instead of iterating:
// a NaN compares false everywhere, so no loop test would end it.
TEST(AdditiveCcd, NonFiniteMotionIsRefusedAtOnce) {
  const Point t0(0, 0, 0), t1(1, 0, 0), t2(0, 1, 0);
  const std::array<Point, 4> start{Point(.2, .2, 1), t0, t1, t2};
  for (const double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
    const std::array<Point, 4> end{Point(.2, .2, bad), t0, t1, t2};
    const CcdResult r = additive_ccd_linear_query(PairKind::point_triangle, start, end);
    EXPECT_EQ(r.status, CcdStatus::non_finite) << to_string(r.status);
    EXPECT_EQ(r.step, 0.0);
    EXPECT_EQ(r.iterations, 0);
  }
  const StencilPath path = [&](double, std::array<Point, 4>& points) { points = start; };
  EXPECT_EQ(additive_ccd_query(PairKind::point_triangle, path, std::nan(""), 1.0).status, CcdStatus::non_finite);
  EXPECT_EQ(additive_ccd_query(PairKind::point_triangle, path, 1.0, std::nan("")).status, CcdStatus::non_finite);
}

// The iteration budget ends a query whose motion is far longer than its gap (a vertex sliding
// 1e-8 above a face needs ~3e7 advances to cross it) with a step that is still safe, after
// exactly the budget; with no budget left the step is the first advance (1 - s) g0 / L, which
// the rate bound alone makes safe. Reference: the gap of the constructed motion is 1e-8 at all t.
TEST(AdditiveCcd, BudgetEndsLongQueriesWithASafeStep) {
  const Point t0(0, 0, 0), t1(1, 0, 0), t2(0, 1, 0);
  const double g = 1e-8;
  const std::array<Point, 4> start{Point(.1, .2, g), t0, t1, t2}, end{Point(.4, .3, g), t0, t1, t2};
  CcdOptions o;
  o.max_iterations = 1000;
  const CcdResult r = additive_ccd_linear_query(PairKind::point_triangle, start, end, 1.0, o);
  EXPECT_EQ(r.status, CcdStatus::budget_exhausted);
  EXPECT_EQ(r.iterations, 1000);
  EXPECT_GT(r.step, 0.0);
  EXPECT_LT(r.step, 1.0);
  o.max_iterations = 0;
  const CcdResult first = additive_ccd_linear_query(PairKind::point_triangle, start, end, 1.0, o);
  EXPECT_EQ(first.status, CcdStatus::budget_exhausted);
  EXPECT_EQ(first.iterations, 0);
  const double rate = (end[0] - start[0]).norm();  // |u_p - mean| + max |u_t - mean|, mean = u_p / 4
  EXPECT_NEAR(first.step, 0.9 * g / rate, 1e-12 * first.step);
}

// ContactPotential::max_step spends at most CcdOptions::max_total_iterations distance
// evaluations over all its queries: a direction 1e12 times the gaps (as from a nearly singular
// Newton step) ends with a step at which nothing touches (its wall time is printed, not asserted:
// the sanitizer build is 100 times slower).
TEST(AdditiveCcd, MaxStepOfAHugeDirectionIsBounded) {
  // Two parallel unit squares (2 triangles each) 1e-3 apart, the upper one sliding by 1e9.
  Eigen::MatrixX3i faces(4, 3);
  faces << 0, 1, 2, 0, 2, 3, 4, 6, 5, 4, 7, 6;
  const ContactSurface surface = ContactSurface::from_faces(8, faces, {0, 0, 0, 0, 1, 1, 1, 1});
  Positions x(8, 3);
  x << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1e-3, 1, 0, 1e-3, 1, 1, 1e-3, 0, 1, 1e-3;
  ContactOptions options;
  options.activation_distance = 1e-4;
  const ContactPotential potential(surface, x, options);
  Positions dx = Positions::Zero(8, 3);
  dx.bottomRows(4).col(0).setConstant(1e9);
  const auto t0 = std::chrono::steady_clock::now();
  const double step = potential.max_step(x, dx);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("max_step of a 1e9 slide over a 1e-3 gap: %.3g in %.3f s\n", step, seconds);
  EXPECT_GT(step, 0.0);
  EXPECT_LE(step, 1.0);
  EXPECT_GT(potential.min_distance(x + step * dx, 1.0), 0.0);
  // With a budget of 10 evaluations for the whole call: a shorter step, still safe.
  options.ccd.max_total_iterations = 10;
  const ContactPotential tight(surface, x, options);
  const double short_step = tight.max_step(x, dx);
  EXPECT_GT(short_step, 0.0);
  EXPECT_LE(short_step, step);
  EXPECT_GT(potential.min_distance(x + short_step * dx, 1.0), 0.0);
  Positions bad = dx;
  bad(5, 2) = std::nan("");
  EXPECT_EQ(potential.max_step(x, bad), 0.0);
}

}  // namespace
}  // namespace tailor::contact::additive_ccd_test
