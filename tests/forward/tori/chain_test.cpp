// Hanging chains of tori: static equilibrium against the closed form (a vertical chain's pair
// k carries the weight of every link below it), and a swinging chain; after every accepted
// step the inscribed meshes are checked for edge-face crossings (must be 0).
#include "forward/tori/chain_simulation.hpp"

#include <gtest/gtest.h>

#include <cstdio>

namespace tailor::tori::chain_test {
namespace {

ChainSpec chain(int count) {
  ChainSpec spec;
  spec.count = count;
  spec.shape = {1.0, 0.2};
  spec.density = 1000.0;
  spec.major_segments = 32;
  spec.minor_segments = 8;
  return spec;
}

// `tolerance`: relative to the top pair's load; Newton stops when no point moves more than
// 1e-10 of the chain's length, which leaves force errors of ~1e-7 of the load for 11 links and
// ~4e-6 for 101 (a 162 m chain).
void expect_vertical_equilibrium(int count, int pair_band = 0, double tolerance = 1e-6) {
  ChainSimulationOptions o;
  o.time_step = 1.0;  // static: implicit Euler's fixed point (chain_simulation.hpp)
  o.pair_band = pair_band;
  ChainSimulation sim(chain(count), o);
  std::vector<ChainStepRecord> records;
  ASSERT_TRUE(sim.relax(1e-10, 200, &records)) << sim.last_result().report();
  for (std::size_t n = 0; n < records.size(); ++n) {
    EXPECT_EQ(records[n].intersections, 0) << "step " << n;
    EXPECT_GT(records[n].min_distance, 0.0) << "step " << n;
  }
  const Vector& q = sim.state();
  const double weight = sim.system().body(1).mass * 9.81;
  const std::vector<TorusPairForce> forces = sim.implicit_term()->pair_forces(q, Vector());
  ASSERT_EQ(static_cast<int>(forces.size()), count - 1);  // neighbours only
  for (const TorusPairForce& f : forces) {
    ASSERT_EQ(f.b, f.a + 1);
    // Link b and everything below it hang from pair (a, b): force on b = (count - b) weights, up.
    EXPECT_NEAR(f.force_on_b.z(), (count - f.b) * weight, tolerance * count * weight) << f.a;
    EXPECT_NEAR(f.force_on_b.head<2>().norm(), 0.0, 1e-8 * weight) << f.a;
    EXPECT_GT(f.distance, 0.0);
    EXPECT_LT(f.distance, sim.activation_distance());
  }
  // The top pair carries the most and sits closest.
  EXPECT_LT(forces.front().distance, forces.back().distance);
  std::printf("%d links: %zu steps, top gap %.3e, bottom gap %.3e (d_hat %.1e)\n", count, records.size(),
              forces.front().distance, forces.back().distance, sim.activation_distance());
}

TEST(TorusChain, ThreeLinksHangInEquilibriumWithTheWeightBelowEachPair) { expect_vertical_equilibrium(3); }
TEST(TorusChain, ElevenLinksHangInEquilibriumWithTheWeightBelowEachPair) { expect_vertical_equilibrium(11); }
TEST(TorusChain, HundredAndOneLinksHangInEquilibriumWithTheWeightBelowEachPair) {
  expect_vertical_equilibrium(101, 2, 1e-5);  // candidate pairs |i - j| <= 2
}

void expect_swing_without_intersections(int count, int steps) {
  ChainSpec spec = chain(count);
  spec.tilt = 0.4;  // released 0.4 rad from the vertical: it swings down through it
  ChainSimulationOptions o;
  o.time_step = 1e-2;
  ChainSimulation sim(spec, o);
  const int last = 6 * (count - 1) + 2;
  const double z0 = sim.state()[last];
  double smallest = std::numeric_limits<double>::infinity();
  for (int n = 0; n < steps; ++n) {
    const ChainStepRecord r = sim.step();
    ASSERT_TRUE(r.converged) << "step " << n << ": " << sim.last_message();
    EXPECT_EQ(r.intersections, 0) << "step " << n;
    ASSERT_GT(sim.min_distance(1e300), 0.0) << "step " << n;
    smallest = std::min(smallest, r.min_distance);
  }
  EXPECT_LT(sim.state()[last], z0);  // the last link fell while swinging towards the vertical
  EXPECT_LT(smallest, sim.activation_distance());  // contacts were active
}

TEST(TorusChain, SwingingChainNeverIntersects) { expect_swing_without_intersections(5, 40); }
TEST(TorusChain, ElevenLinkSwingingChainNeverIntersects) { expect_swing_without_intersections(11, 20); }

}  // namespace
}  // namespace tailor::tori::chain_test
