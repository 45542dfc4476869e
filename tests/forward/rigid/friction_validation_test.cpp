// Validation of lagged IPC friction in implicit Euler steps against Coulomb's law (closed form,
// e.g. Halliday, Resnick & Walker, "Fundamentals of Physics", chapter 6: a block on a plane
// inclined by theta with friction coefficient mu stays at rest when tan(theta) <= mu and
// otherwise slides down with the acceleration a = g (sin(theta) - mu cos(theta)); the smoothed
// static friction creeps below eps_v at the speed its own closed form gives), and of a
// kinematic plate pushing a box at constant speed over a plane with friction: once the box
// moves with the plate, the plate pushes with the sliding friction force mu m g (Newton's first
// law), and no step intersects.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "forward/contact/intersection.hpp"
#include "forward/rigid/friction_term.hpp"
#include "forward/rigid/rigid_gravity_term.hpp"
#include "forward/rigid/rigid_time_stepper.hpp"

namespace tailor::rigid::friction_validation_test {
namespace {

constexpr double kGravity = 9.81;

// A 0.5 m box (125 kg) resting on a fixed ground (top face at z = 0) with gravity tilted by
// theta in the x-z plane: the ground is the inclined plane in its own frame.
struct Incline {
  RigidBodySystem system;
  Model model{system.num_dofs()};
  RigidInertiaTerm* inertia = nullptr;
  RigidContactTerm* contact = nullptr;
  FrictionTerm* friction = nullptr;
  static RigidBodySystem bodies() {
    Eigen::MatrixX3d v;
    Eigen::MatrixX3i f;
    box_surface(Eigen::Vector3d(16, 4, 1), v, f);
    RigidBody ground = rigid_body_from_mesh("ground", v, f, 1000.0, true);
    ground.position = Eigen::Vector3d(0, 0, -0.5);
    box_surface(Eigen::Vector3d(0.5, 0.5, 0.5), v, f);
    RigidBody box = rigid_body_from_mesh("box", v, f, 1000.0);
    box.position = Eigen::Vector3d(-4, 0, 0.25 + 2e-3);
    return RigidBodySystem({ground, box});
  }
  Incline(double theta, double mu, double h) : system(bodies()) {
    inertia = &model.add(std::make_unique<RigidInertiaTerm>(system, h));
    model.add(std::make_unique<RigidGravityTerm>(
        system, kGravity * Eigen::Vector3d(std::sin(theta), 0, -std::cos(theta))));
    contact::ContactOptions c;
    c.activation_distance = 0.01;
    c.stiffness = 1e6;
    contact = &model.add(std::make_unique<RigidContactTerm>(system, c));
    contact::FrictionOptions f;
    f.coefficient = mu;
    f.velocity_threshold = 1e-3;
    friction = &model.add(std::make_unique<FrictionTerm>(*contact, f));
    model.set_elimination(Elimination::dirichlet(system.fixed_dofs(), system.initial_state()));
  }
  RigidStepOptions step_options() {
    RigidStepOptions o;
    o.contact = contact;
    o.friction = friction;
    o.velocity_tolerance = 1e-6;  // IPC's stop: Newton directions below 1e-6 m/s x h
    return o;
  }
};

struct SlideRun {
  std::vector<double> velocity;  // x velocity of the box after each step
  double max_speed_z = 0, min_distance = INFINITY;
  int intersections = 0;
};

SlideRun run_incline(double theta, double mu, double h, int steps) {
  Incline scene(theta, mu, h);
  RigidTimeStepper stepper(scene.system, scene.model, *scene.inertia, NewtonOptions{}, scene.step_options());
  SlideRun run;
  for (int n = 1; n <= steps; ++n) {
    const NewtonResult result = stepper.step();
    EXPECT_TRUE(result.converged()) << "step " << n << "\n" << result.report();
    if (!result.converged()) break;
    run.velocity.push_back(stepper.motion()[1].velocity.x());
    run.min_distance = std::min(run.min_distance, scene.contact->min_distance(stepper.state(), 1.0));
    run.intersections += contact::count_edge_face_intersections(
        scene.system.surface(), scene.system.world_positions(stepper.state()));
    if (n > steps / 2)
      run.max_speed_z = std::max(run.max_speed_z, std::abs(stepper.motion()[1].velocity.z()));
  }
  return run;
}

TEST(FrictionValidation, BoxOnInclineSlidesWithCoulombAcceleration) {
  const double mu = 0.5, h = 0.01;
  for (double degrees : {35.0, 45.0}) {
    const double theta = degrees * M_PI / 180.0;
    const SlideRun run = run_incline(theta, mu, h, 100);
    ASSERT_EQ(run.velocity.size(), 100u);
    // Implicit Euler under a constant force advances the velocity by h a per step exactly.
    const double measured = (run.velocity[99] - run.velocity[49]) / (50 * h);
    const double expected = kGravity * (std::sin(theta) - mu * std::cos(theta));
    std::printf(
        "incline %.0f deg, mu %.2f: acceleration %.6f m/s^2, Coulomb %.6f (rel. error %.2e), min distance "
        "%.2e m\n",
        degrees, mu, measured, expected, std::abs(measured / expected - 1), run.min_distance);
    EXPECT_NEAR(measured, expected, 1e-3 * expected);
    EXPECT_LT(run.max_speed_z, 1e-3);
    EXPECT_EQ(run.intersections, 0);
    EXPECT_GT(run.min_distance, 0.0);
  }
}

TEST(FrictionValidation, BoxOnInclineSticksBelowTheFrictionAngle) {
  const double mu = 0.5, h = 0.01, eps_v = 1e-3;
  for (double degrees : {10.0, 20.0, 25.0}) {  // tan(25 deg) = 0.466 < mu
    const double theta = degrees * M_PI / 180.0;
    const SlideRun run = run_incline(theta, mu, h, 100);
    ASSERT_EQ(run.velocity.size(), 100u);
    double fastest = 0;
    for (std::size_t n = 50; n < run.velocity.size(); ++n)
      fastest = std::max(fastest, std::abs(run.velocity[n]));
    // Smoothed static friction lets a sticking contact creep below eps_v, at the speed where
    // mu N f1(v h) balances the downhill force: f1 = tan(theta) / mu, v = eps_v (1 - sqrt(1 - f1)).
    const double creep = eps_v * (1.0 - std::sqrt(1.0 - std::tan(theta) / mu));
    std::printf("incline %.0f deg, mu %.2f: creep speed %.4e m/s (smoothed model %.4e, eps_v %.0e m/s)\n",
                degrees, mu, fastest, creep, eps_v);
    EXPECT_LT(fastest, eps_v);
    EXPECT_NEAR(std::abs(run.velocity.back()), creep, 5e-3 * creep);
    EXPECT_EQ(run.intersections, 0);
  }
  // Just above the friction angle it slides (and accelerates).
  const SlideRun slide = run_incline(std::atan(mu) + 0.05, mu, h, 60);
  ASSERT_EQ(slide.velocity.size(), 60u);
  EXPECT_GT(slide.velocity.back(), 10 * eps_v);
}

// A kinematic plate (x = x0 + v t) pushes a box over the ground with friction mu.
TEST(FrictionValidation, KinematicPlatePushesBoxAgainstSlidingFriction) {
  Eigen::MatrixX3d v;
  Eigen::MatrixX3i f;
  box_surface(Eigen::Vector3d(20, 4, 1), v, f);
  RigidBody ground = rigid_body_from_mesh("ground", v, f, 1000.0, true);
  ground.position = Eigen::Vector3d(0, 0, -0.5);
  box_surface(Eigen::Vector3d(0.5, 0.5, 0.5), v, f);
  RigidBody box = rigid_body_from_mesh("box", v, f, 1000.0);
  box.position = Eigen::Vector3d(0, 0, 0.25 + 2e-3);
  box_surface(Eigen::Vector3d(0.1, 1.0, 0.6), v, f);  // covers the box's face: corners on its face
  RigidBody plate = rigid_body_from_mesh("plate", v, f, 1000.0);
  plate.position = Eigen::Vector3d(-0.25 - 0.05 - 0.02, 0, 0.32);
  plate.kinematic = true;
  const double speed = 0.5, mu = 0.3, h = 0.01;
  plate.kinematic_velocity = Eigen::Vector3d(speed, 0, 0);
  const RigidBodySystem system({ground, box, plate});
  Model model(system.num_dofs());
  RigidInertiaTerm& inertia = model.add(std::make_unique<RigidInertiaTerm>(system, h));
  model.add(std::make_unique<RigidGravityTerm>(system, Eigen::Vector3d(0, 0, -kGravity)));
  contact::ContactOptions c;
  c.activation_distance = 0.01;
  c.stiffness = 1e6;
  RigidContactTerm& contact = model.add(std::make_unique<RigidContactTerm>(system, c));
  contact::FrictionOptions fo;
  fo.coefficient = mu;
  FrictionTerm& friction = model.add(std::make_unique<FrictionTerm>(contact, fo));
  model.set_elimination(Elimination::dirichlet(system.fixed_dofs(), system.initial_state()));
  RigidStepOptions o;
  o.contact = &contact;
  o.friction = &friction;
  o.velocity_tolerance = 1e-6;
  RigidTimeStepper stepper(system, model, inertia, NewtonOptions{}, o);
  int stages = 0, intersections = 0;
  for (int n = 1; n <= 100; ++n) {
    const NewtonResult result = stepper.step();
    ASSERT_TRUE(result.converged()) << "step " << n << "\n" << result.report();
    stages = std::max(stages, stepper.last_report().kinematic_stages);
    intersections +=
        contact::count_edge_face_intersections(system.surface(), system.world_positions(stepper.state()));
    ASSERT_GT(contact.min_distance(stepper.state(), 10.0), 0.0);
    // The plate's prescribed pose is met exactly.
    EXPECT_NEAR(stepper.state()[12], plate.position.x() + speed * n * h, 1e-12);
  }
  // The box moves with the plate; the plate's contact force on the box balances friction.
  const Vector q = stepper.state();
  const contact::Positions forces = contact.vertex_forces(q);
  // The barrier's x-force on the box comes from the plate (the ground's normals are vertical; the
  // friction term carries the ground's tangential force).
  Eigen::Vector3d on_box_from_plate = Eigen::Vector3d::Zero();
  for (int s = 8; s < 16; ++s) on_box_from_plate += forces.row(s).transpose();
  std::printf(
      "pushed box: speed %.6f m/s (plate %.2f), push %.4f N, mu m g %.4f N, up to %d stages per step\n",
      stepper.motion()[1].velocity.x(), speed, on_box_from_plate.x(), mu * system.body(1).mass * kGravity,
      stages);
  EXPECT_NEAR(stepper.motion()[1].velocity.x(), speed, 1e-3 * speed);
  EXPECT_NEAR(on_box_from_plate.x(), mu * system.body(1).mass * kGravity,
              1e-2 * mu * system.body(1).mass * kGravity);
  EXPECT_EQ(intersections, 0);
}

}  // namespace
}  // namespace tailor::rigid::friction_validation_test
