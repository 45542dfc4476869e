// RodTwistingMomentTerm (forward/rods/twisting_moment_term.hpp): twisting moments as one
// conservative potential of the state. References: central differences (check_energy_term);
// the definition (with the frames at rest the potential is -M theta); invariance under frame
// updates (the same function of x wherever the frames were stored); the moment it represents,
// M (t_0 + t) / (1 + t_0 . t) (its part along t is M, its part normal to t M tan(alpha / 2)).
#include "forward/rods/twisting_moment_term.hpp"

#include <gtest/gtest.h>

#include "adjoint/derivative_check.hpp"
#include "rod_fixtures.hpp"

namespace tailor::twisting_moment_term_test {
namespace {

using namespace tailor::testing;

Vector gradient_of(const EnergyTerm& term, const Vector& x, const Vector& p) {
  Vector g = Vector::Zero(x.size());
  term.add_gradient(x, p, g);
  return g;
}

TEST(RodTwistingMoment, DerivativesAreExactWithStaleFramesAndTurnedEdges) {
  RodSetup s = make_rod(helix(6, 1.0, 0.2, 0.7));
  RodTwistingMomentTerm term(s.rod, {{1, 0.8}, {4, -1.3}, {4, 0.2}});
  EXPECT_EQ(term.num_moments(), 2);  // the two on edge 4 add up
  EXPECT_DOUBLE_EQ(term.moment(1), -1.1);
  term.factor = 0.7;
  // Frames stored ~0.3 rad away from x, and x's edges ~0.4 rad from their rest directions.
  const Vector far = s.rest + 0.3 * uniform_noise(s.model->num_dofs(), 31);
  s.rod->update_reference_frames(far);
  term.update_branches(far);
  const Vector x = s.rest + 0.4 * uniform_noise(s.model->num_dofs(), 32);
  DerivativeCheckOptions o;
  o.initial_step = 1e-4;
  const EnergyTermCheck c = check_energy_term(term, x, s.p, o);
  int checked = 0;
  for (const auto& check : c.checks)  // the term has no parameters: the other checks vanish
    if (check.quantity == "gradient" || check.quantity == "hessian") {
      EXPECT_TRUE(check.passed) << c.table();
      ++checked;
    }
  EXPECT_EQ(checked, 2);
  // A Hessian 1e-4 off fails the same check.
  struct Perturbed final : EnergyTerm {
    const EnergyTerm& inner;
    explicit Perturbed(const EnergyTerm& t) : inner(t) {}
    std::string name() const override { return "perturbed"; }
    void evaluate(const Vector& y, const Vector& q, const EnergyRequest& r) const override {
      inner.evaluate(y, q, r);
      if (r.hessian_values) r.hessian_values[0] *= 1.0 + 1e-4 + 1e-4 * std::abs(r.hessian_values[0]);
    }
    void hessian_pattern(HessianPattern& pattern) const override { inner.hessian_pattern(pattern); }
  };
  const EnergyTermCheck bad = check_energy_term(Perturbed(term), x, s.p, o);
  for (const auto& check : bad.checks)
    if (check.quantity == "hessian") {
      EXPECT_FALSE(check.passed) << bad.table();
    }
}

TEST(RodTwistingMoment, WithFramesAtRestItIsMinusMTheta) {
  RodSetup s = make_rod(helix(6, 1.0, 0.2, 0.7));
  const RodTwistingMomentTerm term(s.rod, {{2, 0.6}});
  Vector x = s.rest + 0.2 * uniform_noise(s.model->num_dofs(), 33);
  EXPECT_NEAR(term.value(x, s.p), -0.6 * x[s.rod->twist_dof(2)], 1e-14);
}

// The energy is one function of the state: frames updated anywhere (here along a path of
// states, as load steps do) give the same value at the same physical state (positions and
// material frames). A force on theta alone, -M theta, changes with every update (theta is
// measured from the stored frame) -- the fault this term fixes.
TEST(RodTwistingMoment, FrameUpdatesDoNotChangeTheFunction) {
  RodSetup s = make_rod(helix(7, 1.0, 0.3, 0.6));
  RodTwistingMomentTerm term(s.rod, {{5, 1.0}});
  const Vector x = s.rest + 0.3 * uniform_noise(s.model->num_dofs(), 34);
  const double before = term.value(x, s.p);
  const double elastic_before = s.twisting->value(x, s.p) + s.bending->value(x, s.p);
  // Move the frames to x in 10 steps (and to intermediate states off the path).
  for (int k = 1; k <= 10; ++k) {
    const Vector at = s.rest + (k / 10.0) * (x - s.rest) + 0.05 * uniform_noise(s.model->num_dofs(), 40 + k);
    s.rod->update_reference_frames(at);
    term.update_branches(at);
  }
  // theta is measured from the stored frames: the same physical state has other twists now.
  // Re-express a state in the new gauge: theta' = theta - (angle from the rest-frame reference
  // director to the updated one), computed on a copy of the rod whose frames stayed at rest.
  const RodSetup at_rest = make_rod(helix(7, 1.0, 0.3, 0.6));
  const RodTwistingMomentTerm rest_term(at_rest.rod, {{5, 1.0}});
  auto regauged = [&](const Vector& z) {
    Vector w = z;
    for (int j = 0; j < s.rod->num_edges(); ++j) {
      const Eigen::Vector3d old_a1 = at_rest.rod->reference_director(z, j);
      const Eigen::Vector3d new_a1 = s.rod->reference_director(z, j);
      const Eigen::Vector3d t = s.rod->edge_vector(z, j).normalized();
      w[s.rod->twist_dof(j)] = z[s.rod->twist_dof(j)] - std::atan2(old_a1.cross(new_a1).dot(t), old_a1.dot(new_a1));
    }
    return w;
  };
  const Vector y = regauged(x);
  // The elastic energy of the re-expressed state is unchanged (a check of the re-expression).
  EXPECT_NEAR(s.twisting->value(y, s.p) + s.bending->value(y, s.p), elastic_before, 1e-12);
  EXPECT_NEAR(term.value(y, s.p), before, 1e-12);
  // And at states around x, re-expressed the same way: one function, not only one value.
  for (int k = 0; k < 5; ++k) {
    const Vector z = x + 0.05 * uniform_noise(s.model->num_dofs(), 60 + k);
    EXPECT_NEAR(term.value(regauged(z), s.p), rest_term.value(z, s.p), 1e-12);
  }
}

// The moment the potential represents, with the frames at the evaluated state (where theta's
// rate is the material frame's spin about t): M along t, and from the positions' generalized
// forces f_1 = -f_0 on the edge's ends the couple e x f_1 = M (t_0 - (t_0 . t) t) / (1 + t_0 . t).
TEST(RodTwistingMoment, RepresentsTheSemiTangentialMoment) {
  RodSetup s = make_rod(straight(4, 3.0));
  RodTwistingMomentTerm term(s.rod, {{2, 1.5}});
  Vector x = s.rest;
  x.segment<3>(s.rod->position_dof(3, 0)) += Eigen::Vector3d(-0.2, 0.5, 0.4);  // turn the last edge
  s.rod->update_reference_frames(x);
  term.update_branches(x);
  const Vector g = gradient_of(term, x, s.p);
  const Eigen::Vector3d f1 = -g.segment<3>(s.rod->position_dof(3, 0)), f0 = -g.segment<3>(s.rod->position_dof(2, 0));
  EXPECT_LT((f0 + f1).norm(), 1e-12);
  EXPECT_NEAR(-g[s.rod->twist_dof(2)], 1.5, 1e-14);
  const Eigen::Vector3d e = s.rod->edge_vector(x, 2), t = e.normalized(), t0 = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d couple = e.cross(f1);
  const Eigen::Vector3d expected = 1.5 * (t0 - t0.dot(t) * t) / (1.0 + t0.dot(t));
  EXPECT_LT((couple - expected).norm(), 1e-10 * expected.norm()) << couple.transpose() << " vs "
                                                                  << expected.transpose();
}

}  // namespace
}  // namespace tailor::twisting_moment_term_test
