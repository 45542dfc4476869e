// Chains of elliptic-tube tori through the same simulation path as the circular ones: a static
// vertical chain carries the weight below each pair (closed form) with 0 mesh crossings, and the
// contact term on an elliptic pair passes the energy-term derivative checks in the state and the
// radii, and its CCD (the surface points' Lipschitz bound) has no false negatives on hard queries.
#include <gtest/gtest.h>

#include <cstdio>
#include <limits>
#include <random>

#include "adjoint/derivative_check.hpp"
#include "forward/tori/chain_simulation.hpp"

namespace tailor::tori::elliptic_chain_test {
namespace {

ChainSpec elliptic_chain(int count, double r1) {
  ChainSpec spec;
  spec.count = count;
  spec.shape = {1.0, 0.2, r1};
  spec.major_segments = 32;
  spec.minor_segments = 8;
  return spec;
}

void expect_vertical_equilibrium(double r1) {
  const int count = 3;
  ChainSimulationOptions o;
  o.time_step = 1.0;  // static: implicit Euler's fixed point (chain_simulation.hpp)
  ChainSimulation sim(elliptic_chain(count, r1), o);
  std::vector<ChainStepRecord> records;
  ASSERT_TRUE(sim.relax(1e-10, 200, &records)) << sim.last_result().report();
  for (std::size_t n = 0; n < records.size(); ++n) {
    EXPECT_EQ(records[n].intersections, 0) << "step " << n;
    EXPECT_GT(records[n].min_distance, 0.0) << "step " << n;
  }
  const double weight = sim.system().body(1).mass * 9.81;
  EXPECT_NEAR(sim.system().body(1).mass, 1000.0 * 2.0 * M_PI * M_PI * 1.0 * 0.2 * r1, 1e-9);
  const std::vector<TorusPairForce> forces = sim.implicit_term()->pair_forces(sim.state(), Vector());
  ASSERT_EQ(static_cast<int>(forces.size()), count - 1);
  for (const TorusPairForce& f : forces) {
    ASSERT_EQ(f.b, f.a + 1);
    EXPECT_NEAR(f.force_on_b.z(), (count - f.b) * weight, 1e-6 * count * weight) << f.a;
    EXPECT_NEAR(f.force_on_b.head<2>().norm(), 0.0, 1e-8 * weight) << f.a;
    EXPECT_GT(f.distance, 0.0);
    EXPECT_LT(f.distance, sim.activation_distance());
  }
  EXPECT_LT(forces.front().distance, forces.back().distance);
  // Hanging straight, each link rests on the one above at their inner equators: the centres are
  // 2R - 2r - gap apart whatever r1, the gap a small fraction of d_hat.
  const double spacing = sim.state()[2] - sim.state()[8];
  EXPECT_NEAR(spacing, 2.0 * (1.0 - 0.2), sim.activation_distance());
  std::printf("r1 = %.2f: %zu steps, top gap %.3e, bottom gap %.3e (d_hat %.1e)\n", r1, records.size(),
              forces.front().distance, forces.back().distance, sim.activation_distance());
}

TEST(EllipticTorusChain, ThreeLinksWithAWideTubeHangWithTheWeightBelowEachPair) {
  expect_vertical_equilibrium(0.3);
}
TEST(EllipticTorusChain, ThreeLinksWithAFlatTubeHangWithTheWeightBelowEachPair) {
  expect_vertical_equilibrium(0.12);
}

TEST(EllipticTorusChain, ContactTermPassesDerivativeChecksInTheStateAndTheRadii) {
  ChainSpec spec = elliptic_chain(2, 0.3);
  spec.fix_first = false;
  spec.gap = 0.01;
  Chain chain = make_chain(spec);
  chain.bodies[1].position += Eigen::Vector3d(0.03, -0.02, 0.0);
  chain.bodies[1].rotation += Eigen::Vector3d(0.05, -0.04, 0.07);
  chain.bodies[0].rotation += Eigen::Vector3d(-0.02, 0.03, 0.01);
  const rigid::RigidBodySystem system(chain.bodies);
  TorusContactOptions o;
  o.activation_distance = 0.05;
  o.stiffness = 10.0;
  o.parameter_offset = 0;
  const TorusContactTerm term(system, chain.shapes, o);
  const Vector q = system.initial_state();
  Vector p(4);
  p << 1.0, 0.2, 1.0, 0.2;
  const double d = term.min_distance(q, p, 1.0);
  ASSERT_GT(d, 0.0);
  ASSERT_LT(d, 0.05);
  DerivativeCheckOptions c;
  c.state_scale = 1e-3;
  c.parameter_floor = 1e-3;
  const EnergyTermCheck check = check_energy_term(term, q, p, c);
  std::printf("%s", check.table().c_str());
  EXPECT_TRUE(check.passed()) << check.table();
}

// Two interlocked elliptic links `gap` apart after a twist (b moved vertically by Newton on its
// height from a gap of 0.05 until the gap is `gap`).
struct Pair {
  rigid::RigidBodySystem system;
  std::vector<TorusShape> shapes;
};
Pair twisted_pair(double gap) {
  ChainSpec spec = elliptic_chain(2, 0.3);
  spec.fix_first = false;
  spec.gap = 0.05;  // room for the twist
  spec.major_segments = 16;
  spec.minor_segments = 6;
  Chain chain = make_chain(spec);
  chain.bodies[1].position += Eigen::Vector3d(0.03, -0.02, 0.0);
  chain.bodies[1].rotation += Eigen::Vector3d(0.05, -0.04, 0.07);
  chain.bodies[0].rotation += Eigen::Vector3d(-0.02, 0.03, 0.01);
  for (int it = 0; it < 20; ++it) {
    const TorusDistance d =
        torus_distance({chain.bodies[0].position, chain.bodies[0].rotation, spec.shape},
                       {chain.bodies[1].position, chain.bodies[1].rotation, spec.shape}, true);
    EXPECT_FALSE(d.degenerate);
    // Damped at first: the surface distance is curved in the height, a full first step overshoots.
    chain.bodies[1].position.z() -= (it < 4 ? 0.9 : 1.0) * (d.distance - gap) / d.gradient[8];
  }
  return {rigid::RigidBodySystem(chain.bodies), chain.shapes};
}

TEST(EllipticTorusChain, CcdHardQueriesHaveNoFalseNegatives) {
  // Reference: the distance sampled at 201 points along the accepted part of each path stays
  // positive. Head-on drops far past contact, a spin that swings b's tube through a, tangent
  // slides, at gaps 1e-2 and 1e-5, and random motions.
  int false_negatives = 0, queries = 0;
  auto run = [&](const Pair& pair, const Vector& dq, const char* what) {
    TorusContactOptions o;
    o.activation_distance = 1e-3;
    const TorusContactTerm term(pair.system, pair.shapes, o);
    const Vector q = pair.system.initial_state();
    EXPECT_GT(term.min_distance(q, Vector(), 1.0), 0.0) << what;
    const double alpha = term.max_step(q, dq);
    ++queries;
    double smallest = std::numeric_limits<double>::infinity();
    for (int k = 0; k <= 200; ++k)
      smallest = std::min(smallest, term.min_distance(q + (alpha * k / 200) * dq, Vector(), 10.0));
    if (alpha > 0.0 && !(smallest > 0.0)) {
      ++false_negatives;
      ADD_FAILURE() << what << ": alpha " << alpha;
    }
    return alpha;
  };
  for (double gap : {1e-2, 1e-5}) {
    const Pair pair = twisted_pair(gap);
    const int n = pair.system.num_dofs();
    EXPECT_EQ(run(pair, Vector::Zero(n), "zero motion"), 1.0);
    Vector drop = Vector::Zero(n);
    drop[6 + 2] = -0.5;
    EXPECT_LT(run(pair, drop, "head-on"), 1.0);
    Vector slide = Vector::Zero(n);
    slide[6 + 1] = 0.02;
    run(pair, slide, "tangent slide");
    Vector spin = Vector::Zero(n);
    spin[6 + 3] = 3.0;
    EXPECT_LT(run(pair, spin, "rotation"), 1.0);
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 20; ++k) {
    const Pair pair = twisted_pair(std::pow(10.0, -2.0 - 4.0 * std::abs(u(rng))));
    Vector dq = Vector::Zero(pair.system.num_dofs());
    for (int i = 0; i < dq.size(); ++i) dq[i] = (i % 6 < 3 ? 0.3 : 1.0) * u(rng);
    run(pair, dq, "random");
  }
  std::printf("elliptic CCD hard queries: %d, false negatives: %d\n", queries, false_negatives);
  EXPECT_EQ(false_negatives, 0);
}

}  // namespace
}  // namespace tailor::tori::elliptic_chain_test
