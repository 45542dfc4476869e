// Implicit Euler dynamics of rigid bodies with IPC contact: the inertia term's derivatives,
// free fall against the closed-form implicit Euler recurrence (z_n = z_0 - g h^2 n (n+1) / 2),
// a spin about a principal axis keeping its axis, and a tilted box dropped on the ground that
// never intersects it (distances and edge-face crossings checked after every step) and comes
// to rest.
#include <gtest/gtest.h>

#include <cstdio>

#include "adjoint/derivative_check.hpp"
#include "forward/contact/intersection.hpp"
#include "forward/rigid/rigid_contact_term.hpp"
#include "forward/rigid/rigid_gravity_term.hpp"
#include "forward/rigid/rigid_time_stepper.hpp"
#include "rigid_scenes.hpp"

namespace tailor::rigid::rigid_dynamics_test {
namespace {

RigidBodySystem single_box(const Eigen::Vector3d& size, const Eigen::Vector3d& w) {
  Eigen::MatrixX3d v;
  Eigen::MatrixX3i f;
  box_surface(size, v, f);
  RigidBody box = rigid_body_from_mesh("box", v, f, 1000.0);
  box.position = Eigen::Vector3d(0.1, -0.2, 1.0);
  box.rotation = w;
  return RigidBodySystem({box});
}

TEST(RigidDynamics, InertiaTermPassesDerivativeChecks) {
  for (double angle : {0.0, 0.4, 2.8}) {
    const RigidBodySystem system =
        single_box(Eigen::Vector3d(1, 2, 3), angle * Eigen::Vector3d(1, -2, 2).normalized());
    RigidInertiaTerm inertia(system, 0.01);
    RigidMotion m;
    m.position = Eigen::Vector3d(0.1, -0.2, 1.0);
    m.velocity = Eigen::Vector3d(1, 0, -2);
    m.rotation = rotation_matrix(Eigen::Vector3d(0.1, 0.2, -0.3));
    m.rotation_rate = rotation_matrix(Eigen::Vector3d(0.3, 0, 0)) - Eigen::Matrix3d::Identity();
    inertia.predict({m});
    const EnergyTermCheck check = check_energy_term(inertia, system.initial_state(), Vector());
    EXPECT_TRUE(check.passed()) << check.table();
  }
}

TEST(RigidDynamics, FreeFallFollowsTheImplicitEulerRecurrence) {
  const RigidBodySystem system = single_box(Eigen::Vector3d(1, 1, 1), Eigen::Vector3d::Zero());
  Model model(system.num_dofs());
  const double h = 0.01, g = 9.81;
  RigidInertiaTerm& inertia = model.add(std::make_unique<RigidInertiaTerm>(system, h));
  model.add(std::make_unique<RigidGravityTerm>(system, Eigen::Vector3d(0, 0, -g)));
  RigidTimeStepper stepper(system, model, inertia);
  for (int n = 1; n <= 20; ++n) {
    ASSERT_TRUE(stepper.step().converged());
    EXPECT_NEAR(stepper.state()[2], 1.0 - g * h * h * n * (n + 1) / 2.0, 1e-10) << n;
    EXPECT_LT(stepper.state().segment<3>(3).norm(), 1e-12);
  }
}

TEST(RigidDynamics, SpinAboutAPrincipalAxisKeepsItsAxis) {
  const RigidBodySystem system = single_box(Eigen::Vector3d(1, 2, 3), Eigen::Vector3d::Zero());
  Model model(system.num_dofs());
  const double h = 0.01, omega = 2.0;
  RigidInertiaTerm& inertia = model.add(std::make_unique<RigidInertiaTerm>(system, h));
  RigidTimeStepper stepper(system, model, inertia);
  stepper.set_velocity(0, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, omega));
  double previous = 0.0;
  for (int n = 1; n <= 200; ++n) {  // 4 rad: the rotation vector wraps past pi
    ASSERT_TRUE(stepper.step().converged());
    const Eigen::Matrix3d R = stepper.motion()[0].rotation;
    EXPECT_NEAR(R(2, 2), 1.0, 1e-12);
    const double angle = std::atan2(R(1, 0), R(0, 0));
    double advance = angle - previous;
    if (advance < -M_PI) advance += 2 * M_PI;
    EXPECT_GT(advance, 0.0);
    EXPECT_LT(advance, omega * h * (1 + 1e-9));  // implicit Euler dissipates, never speeds up
    if (n == 1) {
      EXPECT_NEAR(advance, omega * h, 1e-3 * omega * h);
    }
    previous = angle;
  }
  EXPECT_LE(stepper.state().segment<3>(3).norm(), M_PI + 1e-12);
}

TEST(RigidDynamics, TiltedBoxDroppedOnGroundNeverIntersectsAndComesToRest) {
  const RigidBodySystem system =
      testing::box_on_ground(Eigen::Vector3d(4, 4, 1), Eigen::Vector3d(1, 1, 1), 0.3, Eigen::Vector2d(0, 0),
                             Eigen::Vector3d(0.2, 0.1, 0.0), 500.0);
  Model model(system.num_dofs());
  const double h = 0.01, g = 9.81;
  RigidInertiaTerm& inertia = model.add(std::make_unique<RigidInertiaTerm>(system, h));
  model.add(std::make_unique<RigidGravityTerm>(system, Eigen::Vector3d(0, 0, -g)));
  contact::ContactOptions options;
  options.activation_distance = 0.01;
  options.stiffness = 1e7;
  const RigidContactTerm& contact = model.add(std::make_unique<RigidContactTerm>(system, options));
  model.set_elimination(Elimination::dirichlet(system.fixed_dofs(), system.initial_state()));
  RigidTimeStepper stepper(system, model, inertia);
  ASSERT_EQ(contact::count_edge_face_intersections(system.surface(),
                                                   system.world_positions(system.initial_state())),
            0);
  ASSERT_GT(system.world_positions(system.initial_state()).bottomRows(8).col(2).minCoeff(), 0.1);
  double smallest = std::numeric_limits<double>::infinity();
  int iterations = 0;
  for (int n = 0; n < 100; ++n) {
    const NewtonResult result = stepper.step();
    ASSERT_TRUE(result.converged()) << "step " << n << "\n" << result.report();
    iterations += result.iterations;
    const double distance = contact.min_distance(stepper.state(), 100.0);  // all pairs, exact distances
    ASSERT_GT(distance, 0.0) << "step " << n;
    smallest = std::min(smallest, distance);
    ASSERT_EQ(
        contact::count_edge_face_intersections(system.surface(), system.world_positions(stepper.state())), 0)
        << "step " << n;
  }
  const RigidMotion& box = stepper.motion()[1];
  std::printf(
      "dropped box: 100 steps, %d Newton iterations, smallest distance %.3g m, final height %.5f m, "
      "speed %.2e m/s\n",
      iterations, smallest, box.position.z(), box.velocity.norm());
  EXPECT_LT(box.velocity.norm(), 0.05);
  EXPECT_GT(box.position.z(), 0.5);
  EXPECT_LT(box.position.z(), 0.51);
}

}  // namespace
}  // namespace tailor::rigid::rigid_dynamics_test
