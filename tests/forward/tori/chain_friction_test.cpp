// ChainSimulation with link friction and adaptive barrier stiffness (chain_simulation.hpp): a
// kappa far too small for the chain's weight is raised by IPC's rule (Li et al. 2020, section
// 4.3) and keeps every pair above the distance bound that the same fixed kappa lets the links
// press through; friction between the links damps a swinging chain (the dissipated energy is
// positive and no step crosses); a static relaxation refuses friction.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "forward/rigid/rotation.hpp"
#include "forward/tori/chain_simulation.hpp"

namespace tailor::tori::chain_friction_test {
namespace {

ChainSpec heavy_chain() {
  ChainSpec spec;
  spec.count = 3;
  spec.shape = {1.0, 0.2};
  spec.density = 8000.0;  // steel-like links: a heavy chain
  spec.major_segments = 24;
  spec.minor_segments = 6;
  return spec;
}

// The kappa ChainSimulation picks by default for the chain (one pair at d_hat / 2 carries the
// weight).
double default_stiffness(const ChainSpec& spec, const ChainSimulationOptions& o) {
  ChainSimulationOptions fixed = o;
  fixed.stiffness = 0.0;
  fixed.stiffness_control.adaptive = false;
  return ChainSimulation(spec, fixed).stiffness();
}

struct ChainRun {
  double min_distance = INFINITY;
  double final_stiffness = 0.0;
  bool converged = true;
  int intersections = 0;
};

ChainRun run(const ChainSpec& spec, const ChainSimulationOptions& o, int steps) {
  ChainSimulation sim(spec, o);
  ChainRun r;
  for (int n = 0; n < steps; ++n) {
    const ChainStepRecord record = sim.step();
    if (!record.converged) {
      r.converged = false;
      break;
    }
    r.min_distance = std::min(r.min_distance, record.min_distance);
    r.intersections += std::max(0, record.intersections);
  }
  r.final_stiffness = sim.stiffness();
  return r;
}

TEST(ChainAdaptiveStiffness, RaisesATooSmallKappaAndKeepsPairsApart) {
  const ChainSpec spec = heavy_chain();
  ChainSimulationOptions o;
  o.time_step = 0.01;
  const double d_hat = 1e-2 * spec.shape.minor_radius;  // the default
  const double kappa = default_stiffness(spec, o);
  const double small = 1e-4 * kappa;
  const double bound = o.stiffness_control.distance_fraction * d_hat;  // IPC's threshold

  ChainSimulationOptions fixed = o;
  fixed.stiffness = small;
  const ChainRun f = run(spec, fixed, 40);
  ChainSimulationOptions adaptive = o;
  adaptive.stiffness_control.adaptive = true;
  adaptive.stiffness_control.min_stiffness = small;
  adaptive.stiffness_control.max_stiffness = 1e6 * small;
  const ChainRun a = run(spec, adaptive, 40);
  std::printf("fixed kappa %.3e: min distance %.3e (bound %.3e, %s); adaptive from %.3e: final kappa %.3e, min "
              "distance %.3e (default kappa %.3e)\n",
              small, f.min_distance, bound, f.converged ? "converged" : "failed", small, a.final_stiffness,
              a.min_distance, kappa);
  EXPECT_TRUE(!f.converged || f.min_distance < bound);  // the fixed kappa lets the links press through
  ASSERT_TRUE(a.converged);
  EXPECT_GT(a.final_stiffness, 10.0 * small);
  EXPECT_GT(a.min_distance, bound);
  EXPECT_EQ(a.intersections, 0);
}

// The chain's mechanical energy: potential m g z plus kinetic, with the velocities of the last
// step, v = (T_{n+1} - T_n) / h and omega the rotation vector of R_{n+1} R_n^T over h (world frame).
double mechanical_energy(const ChainSimulation& sim, const Vector& before, double h, double g) {
  double energy = 0.0;
  const Vector& q = sim.state();
  for (int b = 0; b < sim.system().num_bodies(); ++b) {
    const rigid::RigidBody& body = sim.system().body(b);
    if (body.fixed) continue;
    const Eigen::Vector3d v = (q.segment<3>(6 * b) - before.segment<3>(6 * b)) / h;
    const Eigen::Matrix3d R = rigid::rotation_matrix(q.segment<3>(6 * b + 3));
    const Eigen::Vector3d omega =
        rigid::rotation_vector(R * rigid::rotation_matrix(before.segment<3>(6 * b + 3)).transpose()) / h;
    const Eigen::Matrix3d I = R * body.inertia * R.transpose();
    energy += body.mass * g * q[6 * b + 2] + 0.5 * body.mass * v.squaredNorm() + 0.5 * omega.dot(I * omega);
  }
  return energy;
}

TEST(ChainFriction, LinkFrictionDampsASwingingChain) {
  // Released 1.2 rad from the vertical, the links slide on each other as the chain swings down:
  // with friction the chain loses more energy than by implicit Euler's own damping.
  ChainSpec spec = heavy_chain();
  spec.density = 1000.0;
  spec.tilt = 1.2;
  ChainSimulationOptions o;
  o.time_step = 0.0025;
  o.stiffness_control.adaptive = true;
  auto swing = [&](double mu) {
    ChainSimulationOptions with = o;
    with.friction.coefficient = mu;
    ChainSimulation sim(spec, with);
    double energy = 0.0, start = 0.0;
    int sliding = 0, sticking = 0;
    for (int n = 0; n < 320; ++n) {
      const Vector before = sim.state();
      const ChainStepRecord r = sim.step();
      EXPECT_TRUE(r.converged) << "mu " << mu << " step " << n << ": " << sim.last_message();
      if (!r.converged) break;
      EXPECT_EQ(r.intersections, 0);
      EXPECT_GT(r.min_distance, 0.0);
      sliding += r.sliding;
      sticking += r.sticking;
      energy = mechanical_energy(sim, before, o.time_step, -o.gravity.z());
      if (n == 0) start = energy;
    }
    std::printf("mu %.2f: energy lost over 0.8 s %.4f J (of the first step's %.4f J), %d sliding and %d "
                "sticking pair-steps, kappa %.3e\n",
                mu, start - energy, start, sliding, sticking, sim.stiffness());
    return std::make_pair(start - energy, sliding);
  };
  const auto [free_loss, free_sliding] = swing(0.0);
  const auto [friction_loss, friction_sliding] = swing(0.3);
  EXPECT_EQ(free_sliding, 0);  // no friction term, no pairs
  EXPECT_GT(friction_sliding, 0);
  EXPECT_GT(friction_loss, 1.5 * free_loss);
}

TEST(ChainFriction, MeshModelSwingsWithFrictionAndAdaptiveStiffness) {
  // The same options on mesh IPC: rigid::FrictionTerm lagged by the stepper, its adaptive kappa.
  ChainSpec spec = heavy_chain();
  spec.density = 1000.0;
  spec.tilt = 1.2;
  ChainSimulationOptions o;
  o.model = ContactModel::mesh;
  o.time_step = 0.005;
  o.friction.coefficient = 0.3;
  o.stiffness_control.adaptive = true;
  ChainSimulation sim(spec, o);
  ASSERT_NE(sim.mesh_friction(), nullptr);
  int sliding = 0, sticking = 0;
  for (int n = 0; n < 30; ++n) {
    const ChainStepRecord r = sim.step();
    ASSERT_TRUE(r.converged) << "step " << n << ": " << sim.last_message();
    EXPECT_EQ(r.intersections, 0);
    sliding += r.sliding;
    sticking += r.sticking;
  }
  std::printf("mesh model: %d sliding and %d sticking pair-steps, kappa %.3e (from %.3e)\n", sliding, sticking,
              sim.stiffness(), sim.initial_stiffness());
  EXPECT_GT(sliding + sticking, 0);
  EXPECT_GE(sim.stiffness(), sim.initial_stiffness());
}

TEST(ChainFriction, StaticRelaxationRefusesFriction) {
  ChainSimulationOptions o;
  o.time_step = 1.0;
  o.friction.coefficient = 0.3;
  ChainSimulation sim(heavy_chain(), o);
  EXPECT_THROW(sim.relax(1e-10, 5), std::invalid_argument);
  ChainSimulationOptions bad = o;
  bad.friction.coefficient = -0.1;
  EXPECT_THROW(ChainSimulation(heavy_chain(), bad), std::invalid_argument);
  ChainSimulationOptions growth = o;
  growth.friction.coefficient = 0.0;
  growth.stiffness_control.adaptive = true;
  growth.stiffness_control.growth = 1.0;
  EXPECT_THROW(ChainSimulation(heavy_chain(), growth), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::tori::chain_friction_test
