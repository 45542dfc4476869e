// TorusContactTerm: derivative checks in the rigid DOFs, the radii (R, r) and a fixed torus's
// placement (T, w), a deliberately wrong Hessian and wrong placement blocks caught by the same
// checks, and CCD hard queries counted against dense path sampling.
#include "forward/tori/torus_contact_term.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "adjoint/derivative_check.hpp"
#include "forward/rigid/rotation.hpp"
#include "forward/tori/chain.hpp"

namespace tailor::tori::torus_contact_term_test {
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

// The placement of a fixed torus as a parameter: its pose read from p (T, w) instead of q.
Vector placement_of(const rigid::RigidBodySystem& system, int body) {
  return system.initial_state().segment<6>(6 * body);
}

TEST(TorusContactTerm, PassesDerivativeChecksInTheFixedTorusPlacement) {
  // Torus 0 fixed, its pose the parameters p = (T_0, w_0), twisted so that every pair variable
  // enters; and the same with the radii first, p = (R_0, r_0, R_1, r_1, T_0, w_0).
  const Pair pair = twisted_pair(0.01, true);
  const Vector q = pair.system.initial_state();
  TorusContactOptions o = options(0.05, 10.0);
  o.placement_offset = 0;
  const TorusContactTerm term(pair.system, pair.shapes, o);
  ASSERT_EQ(term.num_placements(), 1);
  EXPECT_TRUE(term.placed_by_parameters(0));
  EXPECT_FALSE(term.placed_by_parameters(1));
  const Vector p = placement_of(pair.system, 0);
  EXPECT_EQ(term.active_pairs(q, p), 1);
  // The pose comes from p: moving q's copy of the anchor changes nothing.
  Vector q_moved = q;
  q_moved.segment<3>(0) += Eigen::Vector3d(0.0, 0.0, 0.5);
  EXPECT_EQ(term.min_distance(q_moved, p, 1.0), term.min_distance(q, p, 1.0));
  DerivativeCheckOptions c;
  c.state_scale = 1e-3;
  c.parameter_floor = 1e-3;
  const EnergyTermCheck check = check_energy_term(term, q, p, c);
  std::printf("%s", check.table().c_str());
  EXPECT_TRUE(check.passed()) << check.table();
  int mixed_checks = 0;
  for (const DerivativeCheck& k : check.checks)
    if (k.quantity == "mixed" || k.quantity == "mixed_transpose") mixed_checks += k.passed && !k.vanishing;
  EXPECT_GE(mixed_checks, 2);

  TorusContactOptions both = o;
  both.parameter_offset = 0;
  both.placement_offset = 4;
  const TorusContactTerm term_both(pair.system, pair.shapes, both);
  Vector p_both(10);
  p_both << 1.0, 0.2, 1.0, 0.2, p;
  const EnergyTermCheck check_both = check_energy_term(term_both, q, p_both, c);
  EXPECT_TRUE(check_both.passed()) << check_both.table();

  Vector short_p(5);
  EXPECT_THROW(term.min_distance(q, short_p, 1.0), std::invalid_argument);
}

// The placement term with its mixed block d2E/(dx dp_placement) made wrong: each free torus's
// 6 x 6 block transposed (the anchor's rows used for its columns) or scaled by 1.01.
class WrongPlacementBlock final : public EnergyTerm {
 public:
  WrongPlacementBlock(const TorusContactTerm& term, bool transpose, double scale)
      : term_(term), transpose_(transpose), scale_(scale) {}
  std::string name() const override { return "wrong_placement_block"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override {
    term_.evaluate(x, p, request);
  }
  void hessian_pattern(HessianPattern& pattern) const override { term_.hessian_pattern(pattern); }
  void add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const override {
    term_.add_param_gradient(x, p, gradient_p);
  }
  void add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const override {
    Triplets right;
    term_.add_mixed(x, p, right);
    for (const Triplet& t : right) {
      const int offset = term_.options().placement_offset, body = t.row() / 6;
      if (transpose_)
        mixed.emplace_back(6 * body + (t.col() - offset) % 6,
                           offset + t.row() % 6 + 6 * ((t.col() - offset) / 6), t.value());
      else
        mixed.emplace_back(t.row(), t.col(), scale_ * t.value());
    }
  }

 private:
  const TorusContactTerm& term_;
  bool transpose_;
  double scale_;
};

TEST(TorusContactTerm, PlacementCheckCatchesATransposedOrScaledBlock) {
  const Pair pair = twisted_pair(0.01, true);
  const Vector q = pair.system.initial_state();
  TorusContactOptions o = options(0.05, 10.0);
  o.placement_offset = 0;
  const TorusContactTerm term(pair.system, pair.shapes, o);
  const Vector p = placement_of(pair.system, 0);
  DerivativeCheckOptions c;
  c.state_scale = 1e-3;
  c.parameter_floor = 1e-3;
  for (const bool transpose : {true, false}) {
    const WrongPlacementBlock wrong(term, transpose, 1.01);
    const EnergyTermCheck check = check_energy_term(wrong, q, p, c);
    bool gradient_passed = false, mixed_failed = false;
    for (const DerivativeCheck& k : check.checks) {
      if (k.quantity == "param_gradient") gradient_passed = k.passed;
      if (k.quantity == "mixed") {
        mixed_failed = !k.passed && !k.vanishing;
        std::printf("%s placement block: mixed check best error %.2e\n", transpose ? "transposed" : "scaled",
                    k.best_error);
      }
    }
    EXPECT_TRUE(gradient_passed) << check.table();
    EXPECT_TRUE(mixed_failed) << (transpose ? "transposed" : "scaled") << "\n" << check.table();
  }
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
}  // namespace tailor::tori::torus_contact_term_test
