// RigidContactTerm: derivative checks through x = T + R(w) V with active point-triangle and
// (mollified) edge-edge pairs, the PSD projection, and conservative CCD on rotating bodies.
#include "forward/rigid/rigid_contact_term.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "adjoint/derivative_check.hpp"
#include "forward/core/symmetric_eigen.hpp"
#include "forward/rigid/rigid_gravity_term.hpp"
#include "rigid_scenes.hpp"

namespace tailor::rigid::rigid_contact_term_test {
namespace {

contact::ContactOptions contact_options(double d_hat, double kappa) {
  contact::ContactOptions o;
  o.activation_distance = d_hat;
  o.stiffness = kappa;
  return o;
}

// Counts the active pairs by kind and mollification.
struct ActiveCounts {
  int point_triangle = 0, edge_edge = 0, mollified = 0;
};
ActiveCounts count_active(const RigidContactTerm& term, const RigidBodySystem& system, const Vector& q) {
  ActiveCounts c;
  term.potential().for_each_active(system.world_positions(q), true, [&](const contact::ActivePair& pair) {
    if (pair.kind == contact::PairKind::point_triangle) ++c.point_triangle;
    if (pair.kind == contact::PairKind::edge_edge) ++c.edge_edge;
    if (pair.derivatives.mollified) ++c.mollified;
  });
  return c;
}

TEST(RigidContactTerm, StackedBoxesPassDerivativeChecksWithMollifiedEdges) {
  // Equal boxes, the upper one shifted and slightly rotated: its bottom edges run almost
  // parallel to the lower top edges (mollified), corners sit over faces and edges.
  const RigidBodySystem system =
      testing::box_on_ground(Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(1, 1, 1), 0.03,
                             Eigen::Vector2d(0.2, 0.05), Eigen::Vector3d(0.004, -0.006, 0.002));
  const RigidContactTerm term(system, contact_options(0.1, 10.0));
  const Vector q = system.initial_state();
  const ActiveCounts active = count_active(term, system, q);
  EXPECT_GT(active.point_triangle, 0);
  EXPECT_GT(active.edge_edge, 0);
  EXPECT_GT(active.mollified, 0);
  DerivativeCheckOptions options;
  options.state_scale = 1e-3;
  const EnergyTermCheck check = check_energy_term(term, q, Vector(), options);
  std::printf("%s", check.table().c_str());
  EXPECT_TRUE(check.passed()) << check.table();

  const Eigen::MatrixXd projected = Eigen::MatrixXd(term.hessian(q, Vector(), HessianMode::projected));
  EXPECT_GE(symmetric_eigenvalues(projected).minCoeff(), -1e-9 * projected.norm());
}

TEST(RigidContactTerm, LargeRotationPassesDerivativeChecks) {
  // A box turned by about 2.5 rad (exercising the closed-form Rodrigues branch), one corner
  // down near a large ground.
  Eigen::Vector3d w = 2.5 * Eigen::Vector3d(1, 2, 0.5).normalized();
  RigidBodySystem probe = testing::box_on_ground(Eigen::Vector3d(4, 4, 1), Eigen::Vector3d(1, 1, 1), 0.0,
                                                 Eigen::Vector2d(0.1, 0.2), w);
  const double lowest = probe.world_positions(probe.initial_state()).bottomRows(8).col(2).minCoeff();
  const RigidBodySystem system = testing::box_on_ground(Eigen::Vector3d(4, 4, 1), Eigen::Vector3d(1, 1, 1),
                                                        0.04 - lowest, Eigen::Vector2d(0.1, 0.2), w);
  const RigidContactTerm term(system, contact_options(0.1, 10.0));
  const Vector q = system.initial_state();
  EXPECT_GT(count_active(term, system, q).point_triangle, 0);
  DerivativeCheckOptions options;
  options.state_scale = 1e-3;
  const EnergyTermCheck check = check_energy_term(term, q, Vector(), options);
  std::printf("%s", check.table().c_str());
  EXPECT_TRUE(check.passed()) << check.table();
}

TEST(RigidContactTerm, MassParameterOfGravityPassesDerivativeChecks) {
  const RigidBodySystem system =
      testing::box_on_ground(Eigen::Vector3d(4, 4, 1), Eigen::Vector3d(1, 1, 1), 0.05, Eigen::Vector2d(0, 0),
                             Eigen::Vector3d(0.1, 0, 0));
  const RigidGravityTerm gravity(system, Eigen::Vector3d(0, 0, -9.81), 0);
  Vector q = system.initial_state();
  q[8] -= 0.3;  // the box lowered: non-zero work
  const EnergyTermCheck check = check_energy_term(gravity, q, Vector::Constant(2, 2.0));
  for (const auto& c : check.checks) {
    if (c.quantity != "hessian") {
      EXPECT_TRUE(c.passed) << check.table();
    }
  }
}

TEST(RigidContactTerm, CcdOnSpinningBodyNeverMissesContact) {
  // A long thin bar spinning fast about z above the ground; its rotation sweeps its ends
  // down only if tilted, so tilt it: the straight-line interpolation of the ends between
  // q and q + dq would miss contact that the rotating bar makes.
  Eigen::MatrixX3d v;
  Eigen::MatrixX3i f;
  box_surface(Eigen::Vector3d(4, 4, 1), v, f);
  RigidBody ground = rigid_body_from_mesh("ground", v, f, 1.0, true);
  ground.position = Eigen::Vector3d(0, 0, -0.5);
  box_surface(Eigen::Vector3d(2.0, 0.1, 0.1), v, f);
  RigidBody bar = rigid_body_from_mesh("bar", v, f, 1.0);
  bar.position = Eigen::Vector3d(0, 0, 0.2);
  const RigidBodySystem system({ground, bar});
  const RigidContactTerm term(system, contact_options(0.01, 1.0));
  const Vector q = system.initial_state();
  // Rotate by pi about y: the ends swing through z = 0.2 -/+ 1 (through the ground) and back.
  Vector dq = Vector::Zero(12);
  dq[10] = M_PI;
  const double step = term.max_step(q, dq);
  // The straight interpolation of vertex positions between the end points never goes below
  // z = 0.15; the true motion brings the lowest corner (x = 1, z = -0.05 in the body) to
  // z = 0.2 - sin(a) - 0.05 cos(a), which reaches 0 at a ~ 0.151 rad (t ~ 0.048) and is
  // still 0.015 (0.1 of the initial gap) at a ~ 0.136 (t ~ 0.043).
  EXPECT_GT(step, 0.0);
  EXPECT_LT(step, std::asin(0.15) / M_PI);
  Vector at = q + step * dq;
  EXPECT_GT(term.min_distance(at, 10.0), 0.0);
  // A pure translation away from the ground is unrestricted.
  Vector up = Vector::Zero(12);
  up[8] = 1.0;
  EXPECT_EQ(term.max_step(q, up), 1.0);
}


// CCD of a rigid step with a direction far longer than any gap (a nearly singular Newton step:
// the box spinning by 1e6 rad on the ground) spends a bounded number of distance evaluations
// (CcdOptions::max_total_iterations over the call) and returns a step at which nothing
// touches, also with a budget of 10 evaluations (a shorter step). Its wall time is printed, not
// asserted: the sanitizer build runs this test 100 times slower. A NaN direction is refused with step 0; two bodies translating together by 1e9 are
// not slowed by it (their common translation does not change their distance, and is taken out
// of the rate bound).
TEST(RigidContactTerm, CcdOfHugeOrNonFiniteDirectionsIsBounded) {
  const RigidBodySystem system = testing::box_on_ground(Eigen::Vector3d(4, 4, 1), Eigen::Vector3d(1, 1, 1), 1e-3,
                                                        Eigen::Vector2d(0, 0), Eigen::Vector3d(0.01, 0, 0));
  const RigidContactTerm term(system, contact_options(0.01, 1.0));
  const Vector q = system.initial_state();
  Vector spin = Vector::Zero(12);
  spin.segment<3>(9) << 2e5, 3e5, 1e6;
  const auto t0 = std::chrono::steady_clock::now();
  const double step = term.max_step(q, spin);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("max_step of a 1e6 rad spin 1 mm above the ground: %.3g in %.3f s\n", step, seconds);
  EXPECT_GT(step, 0.0);
  EXPECT_LT(step, 1e-6);
  EXPECT_GT(term.min_distance(q + step * spin, 10.0), 0.0);
  contact::ContactOptions tight_options = contact_options(0.01, 1.0);
  tight_options.ccd.max_total_iterations = 10;
  const RigidContactTerm tight(system, tight_options);
  const double short_step = tight.max_step(q, spin);
  EXPECT_GT(short_step, 0.0);
  EXPECT_LE(short_step, step);
  EXPECT_GT(term.min_distance(q + short_step * spin, 10.0), 0.0);
  Vector bad = spin;
  bad[11] = std::nan("");
  EXPECT_EQ(term.max_step(q, bad), 0.0);
  bad[11] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(term.max_step(q, bad), 0.0);

  // Two free boxes 1 mm apart moving together by 1e9: nothing changes between them.
  RigidBody lower = system.body(1), upper = system.body(1);
  upper.name = "upper";
  upper.position.z() += 1.0 + 1e-3;
  const RigidBodySystem pair({lower, upper});
  const RigidContactTerm together(pair, contact_options(0.01, 1.0));
  Vector fall = Vector::Zero(12);
  fall[2] = fall[8] = -1e9;
  EXPECT_EQ(together.max_step(pair.initial_state(), fall), 1.0);
}

}  // namespace
}  // namespace tailor::rigid::rigid_contact_term_test
