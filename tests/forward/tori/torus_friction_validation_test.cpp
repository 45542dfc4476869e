// Validation of lagged IPC friction between implicit tori in implicit Euler steps against
// Coulomb's law (closed form, e.g. Halliday, Resnick & Walker, "Fundamentals of Physics",
// chapter 6: a block on a plane inclined by theta with friction coefficient mu stays at rest when
// tan(theta) <= mu and otherwise slides down with the acceleration a = g (sin(theta) - mu
// cos(theta))).
//
// Geometry: a large fixed torus lying flat (R = 20, r = 5, axis z) is the floor; the contact is
// on its top circle (radius 20 at z = 5), where the surface normal is +z at every point, so a
// small torus sliding tangentially along y keeps a constant normal (moving 0.1 m along the
// tangent takes the contact 2.5e-4 m off the top circle, a normal tilt of 5e-5 rad). The slider
// is an upright small torus (R = 0.5, r = 0.1, axis x) touching with the bottom of its rim: one
// non-degenerate closest point. Its rotation DOFs are held (a wheel would roll or tip: this is
// the translating block of the textbook problem); gravity is tilted by theta in the y-z plane, the
// floor being the inclined plane in its own frame.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "forward/contact/barrier_stiffness.hpp"
#include "forward/core/elimination.hpp"
#include "forward/rigid/rigid_gravity_term.hpp"
#include "forward/rigid/rigid_time_stepper.hpp"
#include "forward/tori/torus_friction_term.hpp"

namespace tailor::tori::torus_friction_validation_test {
namespace {

constexpr double kGravity = 9.81;
const TorusShape kFloor{20.0, 5.0}, kSlider{0.5, 0.1};
constexpr double kDhat = 1e-3;

struct Incline {
  rigid::RigidBodySystem system;
  Model model{system.num_dofs()};
  rigid::RigidInertiaTerm* inertia = nullptr;
  TorusContactTerm* contact = nullptr;
  TorusFrictionTerm* friction = nullptr;
  static rigid::RigidBodySystem bodies() {
    const rigid::RigidBody floor =
        torus_body("floor", kFloor, 1000.0, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), true, 64, 16, true);
    // Axis along x (a quarter turn about y); the rim's bottom kDhat / 2 above the floor's top.
    const Eigen::Vector3d centre(kFloor.major_radius, 0.0,
                                 kFloor.minor_radius + 0.5 * kDhat + kSlider.minor_radius + kSlider.major_radius);
    const rigid::RigidBody slider =
        torus_body("slider", kSlider, 1000.0, centre, Eigen::Vector3d(0.0, 0.5 * M_PI, 0.0), false, 32, 8, true);
    return rigid::RigidBodySystem({floor, slider});
  }
  Incline(double theta, double mu, double eps_v, double h) : system(bodies()) {
    inertia = &model.add(std::make_unique<rigid::RigidInertiaTerm>(system, h));
    const Eigen::Vector3d g = kGravity * Eigen::Vector3d(0.0, std::sin(theta), -std::cos(theta));
    model.add(std::make_unique<rigid::RigidGravityTerm>(system, g));
    TorusContactOptions c;
    c.activation_distance = kDhat;
    // The pair at d_hat / 2 carries the slider's normal weight (it starts at rest there).
    c.stiffness = contact::stiffness_for_force(system.body(1).mass * kGravity * std::cos(theta), kDhat);
    contact = &model.add(std::make_unique<TorusContactTerm>(system, std::vector<TorusShape>{kFloor, kSlider}, c));
    TorusFrictionOptions f;
    f.friction.coefficient = mu;
    f.friction.velocity_threshold = eps_v;
    friction = &model.add(std::make_unique<TorusFrictionTerm>(system, *contact, f));
    std::vector<int> held = system.fixed_dofs();
    for (int k = 9; k < 12; ++k) held.push_back(k);  // the slider's rotation
    model.set_elimination(Elimination::dirichlet(held, system.initial_state()));
  }
};

struct SlideRun {
  std::vector<double> velocity;  // the slider's y velocity after each step
  double max_speed_z = 0.0, min_distance = INFINITY;
};

SlideRun run_incline(double theta, double mu, double eps_v, double h, int steps) {
  Incline scene(theta, mu, eps_v, h);
  rigid::RigidStepOptions o;
  o.velocity_tolerance = 1e-9;  // Newton directions below 1e-9 m/s x h
  NewtonOptions newton;
  newton.absolute_tolerance = 1e-9 * scene.system.body(1).mass * kGravity;
  rigid::RigidTimeStepper stepper(scene.system, scene.model, *scene.inertia, newton, o);
  SlideRun run;
  for (int n = 1; n <= steps; ++n) {
    // Lagged at the start of the step (the stepper's own hook is for mesh friction).
    scene.friction->lag(stepper.state(), stepper.state(), h);
    EXPECT_EQ(scene.friction->pairs().size(), 1u) << "step " << n;
    const NewtonResult result = stepper.step();
    EXPECT_TRUE(result.converged()) << "step " << n << "\n" << result.report();
    if (!result.converged()) break;
    run.velocity.push_back(stepper.motion()[1].velocity.y());
    run.min_distance = std::min(run.min_distance, scene.contact->min_distance(stepper.state(), Vector(), 1.0));
    if (n > steps / 2) run.max_speed_z = std::max(run.max_speed_z, std::abs(stepper.motion()[1].velocity.z()));
  }
  return run;
}

TEST(TorusFrictionValidation, TorusOnInclineSlidesWithCoulombAcceleration) {
  const double mu = 0.3, h = 0.005, eps_v = 1e-3;
  const int steps = 100;
  for (double degrees : {25.0, 40.0}) {  // tan(25 deg) = 0.466 > mu
    const double theta = degrees * M_PI / 180.0;
    const SlideRun run = run_incline(theta, mu, eps_v, h, steps);
    ASSERT_EQ(run.velocity.size(), static_cast<std::size_t>(steps));
    const double measured = (run.velocity[steps - 1] - run.velocity[steps / 2 - 1]) / (steps / 2 * h);
    const double expected = kGravity * (std::sin(theta) - mu * std::cos(theta));
    std::printf("torus on incline %.0f deg, mu %.2f: acceleration %.6f m/s^2, Coulomb %.6f (rel. error %.2e), "
                "min distance %.3e m\n",
                degrees, mu, measured, expected, std::abs(measured / expected - 1.0), run.min_distance);
    EXPECT_NEAR(measured, expected, 2e-2 * expected);
    EXPECT_LT(run.max_speed_z, 1e-3);
    EXPECT_GT(run.min_distance, 0.0);
  }
}

TEST(TorusFrictionValidation, TorusOnInclineSticksBelowTheFrictionAngle) {
  const double mu = 0.5, h = 0.005, eps_v = 1e-3;
  for (double degrees : {10.0, 20.0}) {  // tan(20 deg) = 0.364 < mu
    const double theta = degrees * M_PI / 180.0;
    const SlideRun run = run_incline(theta, mu, eps_v, h, 60);
    ASSERT_EQ(run.velocity.size(), 60u);
    double fastest = 0.0;
    for (std::size_t n = 30; n < run.velocity.size(); ++n) fastest = std::max(fastest, std::abs(run.velocity[n]));
    // Smoothed static friction creeps below eps_v (slip per step below eps_v h), at the speed where
    // mu N f1(v h) balances the downhill force: f1 = tan(theta) / mu, v = eps_v (1 - sqrt(1 - f1)).
    const double creep = eps_v * (1.0 - std::sqrt(1.0 - std::tan(theta) / mu));
    std::printf("torus on incline %.0f deg, mu %.2f: creep speed %.4e m/s (smoothed model %.4e, eps_v %.0e m/s)\n",
                degrees, mu, fastest, creep, eps_v);
    EXPECT_LT(fastest, eps_v);
    EXPECT_NEAR(std::abs(run.velocity.back()), creep, 2e-2 * creep);
    EXPECT_GT(run.min_distance, 0.0);
  }
}

}  // namespace
}  // namespace tailor::tori::torus_friction_validation_test
