// TorusContactTerm: derivative checks in the rigid DOFs and the radii (R, r), a deliberately
// wrong Hessian caught by the check, and CCD hard queries counted against dense path sampling.
#include "forward/tori/torus_contact_term.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "adjoint/derivative_check.hpp"
#include "forward/rigid/rotation.hpp"
#include "forward/tori/chain.hpp"

namespace tailor::tori {
namespace {

// Two interlocked links `gap` apart, b twisted and shifted off the symmetric pose so that
// every variable enters the distance.
struct Pair {
  rigid::RigidBodySystem system;
  std::vector<TorusShape> shapes;
};
Pair twisted_pair(double gap, bool fix_first = false) {
  ChainSpec spec;
  spec.count = 2;
  spec.shape = {1.0, 0.2};
  spec.gap = gap;
  spec.fix_first = fix_first;
  spec.major_segments = 16;
  spec.minor_segments = 6;
  Chain chain = make_chain(spec);
  chain.bodies[1].position += Eigen::Vector3d(0.03, -0.02, 0.0);
  chain.bodies[1].rotation += Eigen::Vector3d(0.05, -0.04, 0.07);
  chain.bodies[0].rotation += Eigen::Vector3d(-0.02, 0.03, 0.01);
  // b moved vertically (Newton on its height) until the gap is `gap` again after the twist.
  for (int it = 0; it < 20; ++it) {
    const TorusDistance d = torus_distance({chain.bodies[0].position, chain.bodies[0].rotation, spec.shape},
                                           {chain.bodies[1].position, chain.bodies[1].rotation, spec.shape}, true);
    chain.bodies[1].position.z() -= (d.distance - gap) / d.gradient[8];
  }
  return {rigid::RigidBodySystem(chain.bodies), chain.shapes};
}

TorusContactOptions options(double d_hat, double kappa, int parameter_offset = -1) {
  TorusContactOptions o;
  o.activation_distance = d_hat;
  o.stiffness = kappa;
  o.parameter_offset = parameter_offset;
  return o;
}

TEST(TorusContactTerm, PassesDerivativeChecksInTheStateAndTheRadii) {
  const Pair pair = twisted_pair(0.01);
  const TorusContactTerm term(pair.system, pair.shapes, options(0.05, 10.0, 0));
  const Vector q = pair.system.initial_state();
  Vector p(4);
  p << 1.0, 0.2, 1.0, 0.2;
  const double d = term.min_distance(q, p, 1.0);
  ASSERT_GT(d, 0.0);
  ASSERT_LT(d, 0.05);  // active: the check is not vacuous
  EXPECT_EQ(term.active_pairs(q, p), 1);
  DerivativeCheckOptions o;
  o.state_scale = 1e-3;
  o.parameter_floor = 1e-3;
  const EnergyTermCheck check = check_energy_term(term, q, p, o);
  std::printf("%s", check.table().c_str());
  EXPECT_TRUE(check.passed()) << check.table();
  int parameter_checks = 0;
  for (const DerivativeCheck& c : check.checks)
    if (c.quantity == "param_gradient" || c.quantity == "mixed") ++parameter_checks;
  EXPECT_GE(parameter_checks, 2);
}

TEST(TorusContactTerm, DerivativeCheckCatchesAMissingImplicitCorrection) {
  // The Hessian without the IFT term -f_yu f_uu^-1 f_uy (the angles held at their optimum)
  // must fail the Hessian check while the gradient still passes: the check can fail.
  const Pair pair = twisted_pair(0.01);
  TorusContactOptions o = options(0.05, 10.0);
  o.distance.implicit_correction = false;
  const TorusContactTerm term(pair.system, pair.shapes, o);
  DerivativeCheckOptions c;
  c.state_scale = 1e-3;
  const EnergyTermCheck check = check_energy_term(term, pair.system.initial_state(), Vector(), c);
  bool gradient_passed = false, hessian_failed = false;
  for (const DerivativeCheck& k : check.checks) {
    if (k.quantity == "gradient") gradient_passed = k.passed;
    if (k.quantity == "hessian") hessian_failed = !k.passed && !k.vanishing;
  }
  EXPECT_TRUE(gradient_passed) << check.table();
  EXPECT_TRUE(hessian_failed) << check.table();
}

// Distance along the path q + t dq at n + 1 samples of [0, alpha]: the smallest.
double smallest_on_path(const TorusContactTerm& term, const Vector& q, const Vector& dq, double alpha, int n) {
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= n; ++k) best = std::min(best, term.min_distance(q + (alpha * k / n) * dq, Vector(), 10.0));
  return best;
}

TEST(TorusContactTerm, CcdHardQueriesHaveNoFalseNegatives) {
  // Reference: the distance sampled densely along the accepted part of each path must stay
  // positive (a false negative: CCD accepted a step whose path touches). Cases: zero motion,
  // tangent sliding, head-on approach far past contact, rotation through the other's tube,
  // gaps of 1e-8, and random motions.
  int false_negatives = 0, queries = 0;
  auto run = [&](const Pair& pair, const Vector& dq, const char* what) {
    const TorusContactTerm term(pair.system, pair.shapes, options(1e-3, 1.0));
    const Vector q = pair.system.initial_state();
    EXPECT_GT(term.min_distance(q, Vector(), 1.0), 0.0) << what;
    const double alpha = term.max_step(q, dq);
    ++queries;
    EXPECT_GE(alpha, 0.0) << what;
    EXPECT_LE(alpha, 1.0) << what;
    if (alpha > 0.0 && !(smallest_on_path(term, q, dq, alpha, 400) > 0.0)) {
      ++false_negatives;
      ADD_FAILURE() << what << ": alpha " << alpha;
    }
    return alpha;
  };
  for (double gap : {1e-2, 1e-5, 1e-8}) {
    const Pair pair = twisted_pair(gap);
    const int n = pair.system.num_dofs();
    Vector zero = Vector::Zero(n);
    EXPECT_EQ(run(pair, zero, "zero motion"), 1.0);
    Vector up = Vector::Zero(n);
    up[6 + 2] = -0.5;  // b drops onto a (hanging links close their gap downwards): far past contact
    EXPECT_LT(run(pair, up, "head-on"), 1.0);
    Vector slide = Vector::Zero(n);
    slide[6 + 1] = 0.02;  // sideways: along the contact's tangent plane
    run(pair, slide, "tangent slide");
    Vector spin = Vector::Zero(n);
    spin[6 + 3] = 3.0;  // b turns about the x axis: its tube swings through a
    EXPECT_LT(run(pair, spin, "rotation"), 1.0);
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 60; ++k) {
    const Pair pair = twisted_pair(std::pow(10.0, -2.0 - 6.0 * std::abs(u(rng))));
    Vector dq = Vector::Zero(pair.system.num_dofs());
    for (int i = 0; i < dq.size(); ++i) dq[i] = (i % 6 < 3 ? 0.3 : 1.0) * u(rng);
    run(pair, dq, "random");
  }
  std::printf("CCD hard queries: %d, false negatives: %d\n", queries, false_negatives);
  EXPECT_EQ(false_negatives, 0);
}

}  // namespace
}  // namespace tailor::tori
