// The radii (R, r) of every torus as parameters of a static chain's equilibrium: the adjoint
// gradient of the bottom link's height (StaticFunctional through TorusContactTerm's mixed
// derivatives) against the Taylor test (reference: re-solved equilibria at perturbed radii; the
// remainder must fall at rate >= 1.9). Only the contact geometry depends on p: the masses stay.
#include <gtest/gtest.h>

#include <cstdio>

#include "adjoint/parameterization.hpp"
#include "adjoint/static_functional.hpp"
#include "adjoint/taylor_test.hpp"
#include "forward/contact/barrier_stiffness.hpp"
#include "forward/core/elimination.hpp"
#include "forward/rigid/rigid_gravity_term.hpp"
#include "forward/tori/chain.hpp"
#include "forward/tori/torus_contact_term.hpp"
#include "objectives/target_dofs.hpp"

namespace tailor::tori::radius_adjoint_test {
namespace {

TEST(TorusRadiusAdjoint, BottomLinkHeightGradientPassesTheTaylorTest) {
  ChainSpec spec;
  spec.count = 3;
  spec.shape = {1.0, 0.2};
  spec.major_segments = 16;
  spec.minor_segments = 6;
  const Chain chain = make_chain(spec);
  const rigid::RigidBodySystem system(chain.bodies);
  Model model(system.num_dofs());
  model.parameter_layout().add("torus_radii", 2 * spec.count);
  const Eigen::Vector3d gravity(0, 0, -9.81);
  model.add(std::make_unique<rigid::RigidGravityTerm>(system, gravity));
  TorusContactOptions o;
  o.activation_distance = 2e-3;
  const double weight = (spec.count - 1) * system.body(1).mass * 9.81;
  o.stiffness = contact::stiffness_for_force(weight, o.activation_distance);
  o.parameter_offset = 0;
  model.add(std::make_unique<TorusContactTerm>(system, chain.shapes, o));
  // The static Hessian is singular in each free link's turn about the vertical (its contact
  // points lie on that axis): w_z of every free link is held (a component of that turn).
  std::vector<int> fixed = system.fixed_dofs();
  for (int b = 1; b < spec.count; ++b) fixed.push_back(6 * b + 5);
  model.set_elimination(Elimination::dirichlet(fixed, system.initial_state()));

  const int bottom_z = 6 * (spec.count - 1) + 2;
  auto objective = std::make_shared<TargetDofs>(std::vector<int>{bottom_z},
                                                Vector::Constant(1, system.initial_state()[bottom_z]));
  StaticFunctionalOptions options;
  options.newton.absolute_tolerance = 1e-7 * weight;  // the barrier's round-off floor (docs/tori.md)
  StaticFunctional functional(model, identity_map(2 * spec.count), objective,
                              model.elimination().restrict_state(system.initial_state()), options);
  Vector radii(2 * spec.count);
  for (int i = 0; i < spec.count; ++i) radii.segment<2>(2 * i) << spec.shape.major_radius, spec.shape.minor_radius;
  Vector gradient;
  functional.value_and_gradient(radii, gradient);
  ASSERT_TRUE(functional.last_newton().converged()) << functional.last_newton().report();
  // Every radius moves the bottom link (the interlocked gaps open with R and close with r).
  for (int i = 0; i < gradient.size(); ++i) EXPECT_NE(gradient[i], 0.0) << i;
  TaylorTestOptions taylor;
  // Steps that keep the warm-started equilibrium apart at the new radii (the gaps are ~1e-3).
  taylor.initial_step = 1e-5;
  const TaylorTestResult result = taylor_test(functional, radii, taylor);
  std::printf("%s", result.table().c_str());
  EXPECT_TRUE(result.passed()) << result.table();
}

}  // namespace
}  // namespace tailor::tori::radius_adjoint_test
