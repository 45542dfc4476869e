// The placement (T, w) of a chain's fixed top link as the parameters of its static equilibrium
// (TorusContactTerm with placement_offset): the adjoint gradient of the free links' centres
// against the Taylor test, and the direct sensitivity against the rigid translation of the
// whole problem.
#include <gtest/gtest.h>

#include <cstdio>

#include "adjoint/parameterization.hpp"
#include "adjoint/scaled_gradient.hpp"
#include "adjoint/static_functional.hpp"
#include "adjoint/taylor_test.hpp"
#include "forward/contact/barrier_stiffness.hpp"
#include "forward/core/elimination.hpp"
#include "forward/rigid/rigid_gravity_term.hpp"
#include "forward/rigid/rotation.hpp"
#include "forward/tori/chain.hpp"
#include "forward/tori/torus_contact_term.hpp"
#include "objectives/target_positions.hpp"

namespace tailor::tori::placement_adjoint_test {
namespace {

// A hanging chain of `count` links, link 0 fixed with its placement p = (T_0, w_0) the design:
// gravity + the torus barrier, each free link's w_z held (the zero mode of the static Hessian,
// radius_adjoint_test.cpp), objective 1/2 sum_free |T_b - T_b^0|^2.
struct PlacedChain {
  Chain chain;
  rigid::RigidBodySystem system;
  Model model;
  std::vector<int> centres;  // 3-blocks of the free links' T
  double weight = 0.0;

  explicit PlacedChain(int count) : chain(make(count)), system(chain.bodies), model(system.num_dofs()) {
    model.parameter_layout().add("torus_placements", 6);
    const Eigen::Vector3d gravity(0, 0, -9.81);
    model.add(std::make_unique<rigid::RigidGravityTerm>(system, gravity));
    weight = (count - 1) * system.body(1).mass * 9.81;
    TorusContactOptions o;
    o.activation_distance = 2e-3;
    o.stiffness = contact::stiffness_for_force(weight, o.activation_distance);
    o.placement_offset = 0;
    model.add(std::make_unique<TorusContactTerm>(system, chain.shapes, o));
    std::vector<int> fixed = system.fixed_dofs();
    for (int b = 1; b < count; ++b) {
      fixed.push_back(6 * b + 5);
      centres.push_back(2 * b);
    }
    model.set_elimination(Elimination::dirichlet(fixed, system.initial_state()));
  }
  static Chain make(int count) {
    ChainSpec spec;
    spec.count = count;
    spec.shape = {1.0, 0.2};
    spec.major_segments = 16;
    spec.minor_segments = 6;
    return make_chain(spec);
  }
  Vector placement() const { return system.initial_state().head<6>(); }
  StaticFunctional functional() {
    Matrix targets(static_cast<Eigen::Index>(centres.size()), 3);
    for (std::size_t i = 0; i < centres.size(); ++i)
      targets.row(static_cast<Eigen::Index>(i)) =
          system.initial_state().segment<3>(3 * centres[i]).transpose();
    StaticFunctionalOptions options;
    options.newton.absolute_tolerance = 1e-7 * weight;  // the barrier's round-off floor (docs/tori.md)
    return StaticFunctional(model, identity_map(6), std::make_shared<TargetPositions>(3, centres, targets),
                            model.elimination().restrict_state(system.initial_state()), options);
  }
};

// Reference: re-solved equilibria at perturbed placements; the remainder must fall at rate
// >= 1.9 after a first-order regime of rate ~1. With the gradient scaled by 1.001 it must fail.
TEST(TorusPlacementAdjoint, FreeLinkCentresGradientPassesTheTaylorTest) {
  PlacedChain chain(3);
  StaticFunctional functional = chain.functional();
  Vector gradient;
  functional.value_and_gradient(chain.placement(), gradient);
  ASSERT_TRUE(functional.last_newton().converged()) << functional.last_newton().report();
  TaylorTestOptions taylor;
  taylor.initial_step = 1e-5;
  // Directions of unit size in each entry (lengths in units of R = 1, angles in radians): the
  // default floor 1e-2 of a zero placement would leave J's change at round-off.
  taylor.direction_floor = 1.0;
  const TaylorTestResult result = taylor_test(functional, chain.placement(), taylor);
  std::printf("%s", result.table().c_str());
  EXPECT_TRUE(result.passed()) << result.table();
  EXPECT_NEAR(result.rate0, 1.0, 0.1);
  EXPECT_GE(result.rate1, 1.9);

  ScaledGradient wrong(functional, 1.001);
  const TaylorTestResult bad = taylor_test(wrong, chain.placement(), taylor);
  EXPECT_EQ(bad.status, TaylorStatus::failed) << bad.table();
}

// Reference (closed form, no code of ours): gravity is uniform and the barrier depends on
// relative poses only, so translating the anchor by dT translates the whole static problem and
// its equilibrium: dT_b/dT_anchor = I and dw_b/dT_anchor = 0 for every free link b; hence also
// dJ/dT_anchor = sum_free (T_b - T_b^0); the links' axes do not tilt.
TEST(TorusPlacementAdjoint, MovingTheAnchorTranslatesTheHangingChainRigidly) {
  PlacedChain chain(4);
  StaticFunctional functional = chain.functional();
  const Vector z = chain.placement();
  Vector gradient;
  functional.value_and_gradient(z, gradient);
  ASSERT_TRUE(functional.last_newton().converged()) << functional.last_newton().report();
  const Matrix dx = functional.state_sensitivity(z);
  ASSERT_EQ(dx.cols(), 6);
  const Vector& x = functional.state();
  Eigen::Vector3d drift = Eigen::Vector3d::Zero();
  double worst_centre = 0.0, worst_tilt = 0.0, worst_null = 0.0;
  for (int b = 1; b < chain.system.num_bodies(); ++b) {
    drift += x.segment<3>(6 * b) - chain.system.initial_state().segment<3>(6 * b);
    const Eigen::Vector3d w = x.segment<3>(6 * b + 3);
    for (int axis = 0; axis < 3; ++axis) {
      worst_centre =
          std::max(worst_centre, (dx.col(axis).segment<3>(6 * b) - Eigen::Vector3d::Unit(axis)).norm());
      // The link's orientation through its symmetry axis n = R(w) e_z (torus.hpp), horizontal in a
      // hanging chain. Two turns are symmetries of the static problem: the spin about n (the torus)
      // and the turn about the vertical (its contact points lie on the vertical through its
      // centre); held only by w_z, they leave a near-null mode whose share of dw/dT is amplified
      // round-off. They move n horizontally; the third turn tilts n out of the horizontal: dn_z.
      const Eigen::Vector3d dw = dx.col(axis).segment<3>(6 * b + 3);
      const double eps = 1e-3;
      const Eigen::Vector3d dn =
          (rigid::rotation_matrix(w + eps * dw) - rigid::rotation_matrix(w - eps * dw)) *
          Eigen::Vector3d::UnitZ() / (2.0 * eps);
      worst_tilt = std::max(worst_tilt, std::abs(dn.z()));
      worst_null = std::max(worst_null, dn.norm());
    }
  }
  std::printf(
      "anchor translation: max |dT_b/dT_anchor - I| = %.2e, max |dn_b,z/dT_anchor| = %.2e (|dn_b/dT_anchor| "
      "%.2e, the null mode); dJ/dT_anchor = "
      "(%.6e, %.6e, %.6e), sum_free (T_b - T_b^0) = (%.6e, %.6e, %.6e)\n",
      worst_centre, worst_tilt, worst_null, gradient[0], gradient[1], gradient[2], drift[0], drift[1],
      drift[2]);
  EXPECT_LT(worst_centre, 1e-6);
  EXPECT_LT(worst_tilt, 1e-6);
  EXPECT_GT(std::abs(drift.z()), 1e-4);  // the chain sagged: the gradient reference is not vacuous
  EXPECT_LT((gradient.head<3>() - drift).norm(), 1e-6 * drift.norm());
  // A turn of the anchor about a horizontal axis swings the links below it: not a zero column.
  EXPECT_GT(dx.col(3).norm() + dx.col(4).norm(), 1e-3);
}

}  // namespace
}  // namespace tailor::tori::placement_adjoint_test
