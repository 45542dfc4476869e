// TorusFrictionTerm: derivative checks in the rigid DOFs on both branches of the smoothing
// (sticking |u| < eps and sliding |u| > eps), for circular and elliptic pairs; a Hessian without
// the rotational curvature term and a scaled gradient caught by the same checks; the lagged data
// (normal force, closest points, tangent basis) against their definitions.
#include "forward/tori/torus_friction_term.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "adjoint/derivative_check.hpp"
#include "forward/contact/barrier.hpp"
#include "forward/rigid/rotation.hpp"
#include "forward/tori/chain.hpp"

namespace tailor::tori::torus_friction_term_test {
namespace {

// Two interlocked links `gap` apart, b twisted and shifted off the symmetric pose so that the
// closest points sit off the bodies' centres and every DOF moves them.
struct Pair {
  rigid::RigidBodySystem system;
  std::vector<TorusShape> shapes;
};
Pair twisted_pair(double gap, const TorusShape& shape) {
  ChainSpec spec;
  spec.count = 2;
  spec.shape = shape;
  spec.gap = gap;
  spec.fix_first = false;
  spec.major_segments = 32;
  spec.minor_segments = 6;
  Chain chain = make_chain(spec);
  chain.bodies[1].position += Eigen::Vector3d(0.03, -0.02, 0.0);
  chain.bodies[1].rotation += Eigen::Vector3d(0.05, -0.04, 0.07);
  chain.bodies[0].rotation += Eigen::Vector3d(-0.02, 0.03, 0.01);
  for (int it = 0; it < 20; ++it) {
    const TorusDistance d = torus_distance({chain.bodies[0].position, chain.bodies[0].rotation, shape},
                                           {chain.bodies[1].position, chain.bodies[1].rotation, shape}, true);
    chain.bodies[1].position.z() -= (d.distance - gap) / d.gradient[8];
  }
  return {rigid::RigidBodySystem(chain.bodies), chain.shapes};
}

TorusContactOptions contact_options() {
  TorusContactOptions o;
  o.activation_distance = 0.05;
  o.stiffness = 10.0;
  return o;
}

TorusFrictionOptions friction_options(double mu = 0.4, double eps_v = 0.1) {
  TorusFrictionOptions o;
  o.friction.coefficient = mu;
  o.friction.velocity_threshold = eps_v;
  return o;
}

// A start of the step displaced from q by `size` in a random direction: the slip at q is of that
// order (h = 0.01, eps = eps_v h = 1e-3).
Vector displaced(const Vector& q, double size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vector d(q.size());
  for (Eigen::Index i = 0; i < d.size(); ++i) d[i] = u(rng);
  return q + size * d / d.lpNorm<Eigen::Infinity>();
}

EnergyTermCheck check(const EnergyTerm& term, const Vector& q) {
  DerivativeCheckOptions o;
  o.state_scale = 1e-2;  // steps (<= 1e-5) well inside the branch of |u| the test is on
  return check_energy_term(term, q, Vector(), o);
}

void expect_passes(const TorusShape& shape, double slip, bool sliding) {
  const Pair pair = twisted_pair(0.01, shape);
  const TorusContactTerm contact(pair.system, pair.shapes, contact_options());
  TorusFrictionTerm friction(pair.system, contact, friction_options());
  const Vector q = pair.system.initial_state();
  friction.lag(q, displaced(q, slip, 3), 0.01);
  ASSERT_EQ(friction.pairs().size(), 1u);
  EXPECT_NEAR(friction.threshold(), 1e-3, 1e-15);
  const auto [n_sliding, n_sticking] = friction.sliding_and_sticking(q);
  EXPECT_EQ(n_sliding, sliding ? 1 : 0);
  EXPECT_EQ(n_sticking, sliding ? 0 : 1);
  const EnergyTermCheck c = check(friction, q);
  std::printf("%s", c.table().c_str());
  EXPECT_TRUE(c.passed()) << c.table();
}

TEST(TorusFrictionTerm, PassesDerivativeChecksWhileSticking) { expect_passes({1.0, 0.2}, 2e-4, false); }
TEST(TorusFrictionTerm, PassesDerivativeChecksWhileSliding) { expect_passes({1.0, 0.2}, 2e-2, true); }
TEST(TorusFrictionTerm, PassesDerivativeChecksOnAnEllipticPairWhileSliding) {
  expect_passes({1.0, 0.2, 0.14}, 2e-2, true);
}

TEST(TorusFrictionTerm, DerivativeCheckCatchesAMissingRotationalCurvature) {
  // Without sum_i (g_x)_i d2x_i/dw2 the Hessian check fails while the gradient still passes.
  const Pair pair = twisted_pair(0.01, {1.0, 0.2});
  const TorusContactTerm contact(pair.system, pair.shapes, contact_options());
  TorusFrictionOptions o = friction_options();
  o.rotation_curvature = false;
  TorusFrictionTerm friction(pair.system, contact, o);
  const Vector q = pair.system.initial_state();
  friction.lag(q, displaced(q, 2e-2, 3), 0.01);
  const EnergyTermCheck c = check(friction, q);
  bool gradient_passed = false, hessian_failed = false;
  for (const DerivativeCheck& k : c.checks) {
    if (k.quantity == "gradient") gradient_passed = k.passed;
    if (k.quantity == "hessian") hessian_failed = !k.passed && !k.vanishing;
  }
  std::printf("without the rotational curvature term:\n%s", c.table().c_str());
  EXPECT_TRUE(gradient_passed) << c.table();
  EXPECT_TRUE(hessian_failed) << c.table();
}

// The friction term with its gradient scaled by 1.01 (the Hessian left): the gradient check
// must reject it.
class ScaledGradientTerm final : public EnergyTerm {
 public:
  explicit ScaledGradientTerm(const EnergyTerm& inner) : inner_(inner) {}
  std::string name() const override { return "scaled_" + inner_.name(); }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override {
    Vector g = Vector::Zero(x.size());
    EnergyRequest r = request;
    if (request.gradient) r.gradient = &g;
    inner_.evaluate(x, p, r);
    if (request.gradient) *request.gradient += 1.01 * g;
  }
  void hessian_pattern(HessianPattern& pattern) const override { inner_.hessian_pattern(pattern); }

 private:
  const EnergyTerm& inner_;
};

TEST(TorusFrictionTerm, DerivativeCheckCatchesAScaledGradient) {
  const Pair pair = twisted_pair(0.01, {1.0, 0.2});
  const TorusContactTerm contact(pair.system, pair.shapes, contact_options());
  TorusFrictionTerm friction(pair.system, contact, friction_options());
  const Vector q = pair.system.initial_state();
  friction.lag(q, displaced(q, 2e-2, 3), 0.01);
  const ScaledGradientTerm scaled(friction);
  const EnergyTermCheck c = check(scaled, q);
  bool gradient_failed = false;
  for (const DerivativeCheck& k : c.checks)
    if (k.quantity == "gradient") gradient_failed = !k.passed;
  std::printf("gradient scaled by 1.01:\n%s", c.table().c_str());
  EXPECT_TRUE(gradient_failed) << c.table();
}

TEST(TorusFrictionTerm, LagsTheBarrierForceAndTheClosestPoints) {
  const Pair pair = twisted_pair(0.01, {1.0, 0.2});
  const TorusContactTerm contact(pair.system, pair.shapes, contact_options());
  TorusFrictionTerm friction(pair.system, contact, friction_options());
  const Vector q = pair.system.initial_state();
  friction.lag(q, q, 0.01);
  ASSERT_EQ(friction.pairs().size(), 1u);
  const TorusFrictionPair& f = friction.pairs()[0];
  // lambda = |dB/dd| of the contact term's pair force: |force_on_b| = lambda |dd/dT_b| = lambda.
  const std::vector<TorusPairForce> forces = contact.pair_forces(q, Vector());
  ASSERT_EQ(forces.size(), 1u);
  EXPECT_NEAR(f.stencil.normal_force, forces[0].force_on_b.norm(), 1e-9 * forces[0].force_on_b.norm());
  // The force on b is along the lagged normal (from a to b), the tangent basis orthogonal to it.
  EXPECT_GT(forces[0].force_on_b.normalized().dot(f.normal), 1.0 - 1e-9);
  const Eigen::Matrix<double, 2, 3> Pt = f.stencil.tangent.block<2, 3>(0, 0);
  EXPECT_LT((Pt * f.normal).norm(), 1e-12);
  EXPECT_LT((Pt * Pt.transpose() - Eigen::Matrix2d::Identity()).norm(), 1e-12);
  // The material points are the closest points: |x_b - x_a| = d on the two surfaces.
  const Eigen::Vector3d x_a = q.segment<3>(0) + rigid::rotation_matrix(q.segment<3>(3)) * f.material_a;
  const Eigen::Vector3d x_b = q.segment<3>(6) + rigid::rotation_matrix(q.segment<3>(9)) * f.material_b;
  EXPECT_NEAR((x_b - x_a).norm(), f.distance, 1e-12);
  // Zero displacement from the start: the potential is mu lambda f0(0) = mu lambda eps / 3, no force.
  double value = 0.0;
  Vector g = Vector::Zero(q.size());
  EnergyRequest r;
  r.value = &value;
  r.gradient = &g;
  friction.evaluate(q, Vector(), r);
  EXPECT_NEAR(value, 0.4 * f.stencil.normal_force * 1e-3 / 3.0, 1e-15);
  EXPECT_LT(g.norm(), 1e-12);
}

TEST(TorusFrictionTerm, RejectsBadInput) {
  const Pair pair = twisted_pair(0.01, {1.0, 0.2});
  const TorusContactTerm contact(pair.system, pair.shapes, contact_options());
  EXPECT_THROW(TorusFrictionTerm(pair.system, contact, friction_options(-0.1)), std::invalid_argument);
  EXPECT_THROW(TorusFrictionTerm(pair.system, contact, friction_options(0.3, 0.0)), std::invalid_argument);
  TorusContactOptions radii = contact_options();
  radii.parameter_offset = 0;
  const TorusContactTerm by_parameters(pair.system, pair.shapes, radii);
  EXPECT_THROW(TorusFrictionTerm(pair.system, by_parameters, friction_options()), std::invalid_argument);
  TorusFrictionTerm friction(pair.system, contact, friction_options());
  const Vector q = pair.system.initial_state();
  EXPECT_THROW(friction.lag(q, q, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::tori::torus_friction_term_test
