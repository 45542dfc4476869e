// Forces and torques on rigid bodies: derivative checks; a torque does the work of a true moment
// (at the reference rotation, the generalized force on w is J^T tau with dR R^T = [J dw]); a
// cube (isotropic inertia) turned to a generic orientation and driven by a constant world torque
// spins about the torque's axis with angle tau t^2 / (2 I) (Euler's equations: dL/dt = tau,
// L = I omega), which a load on the rotation vector misses; and a box on the ground under a
// torque reaches the static moment balance: the contact moment about its centre is -tau.
#include "forward/rigid/rigid_load_term.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>

#include "adjoint/derivative_check.hpp"
#include "forward/rigid/rigid_contact_term.hpp"
#include "forward/rigid/rigid_gravity_term.hpp"
#include "forward/rigid/rigid_time_stepper.hpp"
#include "rigid_scenes.hpp"

namespace tailor::rigid::rigid_load_term_test {
namespace {

Vector loads(const Eigen::Vector3d& force, const Eigen::Vector3d& torque) {
  Vector l(6);
  l << force, torque;
  return l;
}

TEST(RigidLoadTerm, PassesDerivativeChecksAwayFromItsReference) {
  for (double angle : {0.0, 0.4, 2.8}) {
    Vector reference(6), q(6);
    reference << 0.1, 0.2, 0.3, angle * Eigen::Vector3d(1, -2, 2).normalized();
    q = reference;
    q.segment<3>(3) += Eigen::Vector3d(0.05, -0.1, 0.02);
    const RigidLoadTerm term(loads(Eigen::Vector3d(1, -2, 3), Eigen::Vector3d(0.5, 2.0, -1.0)), reference);
    const EnergyTermCheck check = check_energy_term(term, q, Vector());
    EXPECT_TRUE(check.passed()) << check.table();
  }
}

TEST(RigidLoadTerm, TorqueDoesTheWorkOfATrueMoment) {
  const Eigen::Vector3d w(0.7, -1.1, 0.4), tau(0.3, -0.5, 2.0);
  Vector q(6);
  q << 0, 0, 0, w;
  const RigidLoadTerm term(loads(Eigen::Vector3d::Zero(), tau), q);
  Vector g = Vector::Zero(6);
  term.add_gradient(q, Vector(), g);
  // J: the world angular increment per dw, from dR R^T = [J dw] by central differences.
  Eigen::Matrix3d J;
  const double h = 1e-6;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Matrix3d dR = (rotation_matrix(w + h * Eigen::Vector3d::Unit(k)) -
                                rotation_matrix(w - h * Eigen::Vector3d::Unit(k))) /
                               (2 * h) * rotation_matrix(w).transpose();
    J.col(k) = Eigen::Vector3d(dR(2, 1), dR(0, 2), dR(1, 0));
  }
  EXPECT_LT((-g.segment<3>(3) - J.transpose() * tau).norm(), 1e-8 * tau.norm());
  EXPECT_GT((J.transpose() * tau - tau).norm(), 0.1 * tau.norm());  // not the load on w
}

// A load tau . (w - w0) on the rotation vector: what the term did before torques were moments.
class RotationVectorLoad final : public EnergyTerm {
 public:
  RotationVectorLoad(const Eigen::Vector3d& tau, const Eigen::Vector3d& w0) : tau_(tau), w0_(w0) {}
  std::string name() const override { return "rotation_vector_load"; }
  void evaluate(const Vector& x, const Vector&, const EnergyRequest& r) const override {
    if (r.value) *r.value -= tau_.dot(x.segment<3>(3) - w0_);
    if (r.gradient) r.gradient->segment<3>(3) -= tau_;
  }

 private:
  Eigen::Vector3d tau_, w0_;
};

// The rotation after `steps` of h under a constant world torque tau about z, from a generic w0.
void spin_up(bool true_moment, int steps, double h, double tau, double& inertia, Eigen::Matrix3d& turn) {
  Eigen::MatrixX3d v;
  Eigen::MatrixX3i f;
  box_surface(Eigen::Vector3d(1, 1, 1), v, f);
  RigidBody cube = rigid_body_from_mesh("cube", v, f, 6.0);  // 6 kg: I = m a^2 / 6 = 1 kg m^2
  cube.rotation = Eigen::Vector3d(0.9, -0.6, 0.4);
  const RigidBodySystem system({cube});
  inertia = cube.inertia(0, 0);
  Model model(system.num_dofs());
  RigidInertiaTerm& term = model.add(std::make_unique<RigidInertiaTerm>(system, h));
  RigidStepOptions o;
  o.velocity_tolerance = 1e-7;  // IPC's stop on the Newton direction: residuals reach round-off first
  if (true_moment) {
    o.loads = &model.add(std::make_unique<RigidLoadTerm>(
        loads(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, tau)), system.initial_state()));
  } else {
    model.add(std::make_unique<RotationVectorLoad>(Eigen::Vector3d(0, 0, tau), cube.rotation));
  }
  RigidTimeStepper stepper(system, model, term, NewtonOptions{}, o);
  for (int n = 0; n < steps; ++n) {
    const NewtonResult r = stepper.step();
    ASSERT_TRUE(r.converged()) << n << " " << r.report();
  }
  turn = stepper.motion()[0].rotation * rotation_matrix(cube.rotation).transpose();
}

TEST(RigidLoadTerm, ConstantTorqueSpinsAGenericallyTurnedCubeAboutItsAxis) {
  const int steps = 100;
  const double h = 0.01, tau = 0.5;
  double I = 0;
  Eigen::Matrix3d R;
  spin_up(true, steps, h, tau, I, R);
  const Eigen::AngleAxisd turn(R);
  EXPECT_NEAR(I, 1.0, 1e-12);
  // Implicit Euler of theta'' = tau / I: theta_n = h^2 (tau / I) n (n + 1) / 2.
  const double expected = h * h * tau / I * steps * (steps + 1) / 2.0;
  const double axis_error = (turn.axis() - Eigen::Vector3d::UnitZ()).norm();
  std::printf("torque on a turned cube: angle %.6f rad (expected %.6f), axis error %.2e\n", turn.angle(),
              expected, axis_error);
  EXPECT_LT(axis_error, 1e-6);
  EXPECT_NEAR(turn.angle(), expected, 1e-2 * expected);
  spin_up(false, steps, h, tau, I, R);
  const Eigen::AngleAxisd wrong(R);
  std::printf("the same as a load on the rotation vector: angle %.6f rad, axis error %.2e\n", wrong.angle(),
              (wrong.axis() - Eigen::Vector3d::UnitZ()).norm());
  EXPECT_GT((wrong.axis() - Eigen::Vector3d::UnitZ()).norm(), 1e-2);
}

TEST(RigidLoadTerm, BoxUnderTorqueReachesTheStaticMomentBalance) {
  // Off the ground face's diagonal, so that every pair's normal is vertical (the held x, y and
  // spin then carry no reaction).
  const RigidBodySystem system =
      testing::box_on_ground(Eigen::Vector3d(4, 4, 1), Eigen::Vector3d(1, 1, 1), 0.005, Eigen::Vector2d(1, 1),
                             Eigen::Vector3d::Zero(), 1.0);
  const double g = 9.81, torque = 0.2;  // about y: the box tilts onto an edge until contact balances it
  Model model(system.num_dofs());
  model.add(std::make_unique<RigidGravityTerm>(system, Eigen::Vector3d(0, 0, -g)));
  contact::ContactOptions c;
  c.activation_distance = 0.01;
  c.stiffness = 1e5;
  const RigidContactTerm& contact = model.add(std::make_unique<RigidContactTerm>(system, c));
  Vector l = Vector::Zero(12);
  l[10] = torque;
  RigidLoadTerm& load = model.add(std::make_unique<RigidLoadTerm>(l, system.initial_state()));
  std::vector<int> fixed = system.fixed_dofs();
  for (int dof : {6, 7, 11}) fixed.push_back(dof);  // frictionless: hold x, y and the spin about z
  model.set_elimination(Elimination::dirichlet(fixed, system.initial_state()));
  NewtonOptions options;
  options.reference_residual = system.body(1).mass * g;  // re-solves start next to the equilibrium
  NewtonSolver newton(model, options);
  Vector y = model.elimination().restrict_state(system.initial_state());
  int lags = 0;
  for (; lags < 20; ++lags) {  // the torque's reference moved to each solution until it stays
    const Vector before = y;
    const NewtonResult r = newton.solve(Vector(), y);
    ASSERT_TRUE(r.converged()) << r.report();
    load.set_reference(model.state(y, Vector()));
    if ((y - before).lpNorm<Eigen::Infinity>() < 1e-13) break;
  }
  const Vector q = model.state(y, Vector());
  const contact::Positions x = contact.bodies().positions(q), f = contact.vertex_forces(q);
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero();
  const Eigen::Vector3d centre = q.segment<3>(6);
  for (int v = 8; v < 16; ++v) {
    force += f.row(v).transpose();
    moment += (x.row(v).transpose() - centre).cross(f.row(v).transpose());
  }
  std::printf(
      "box under torque: %d re-lags, tilt %.3e rad, contact moment (%.3e, %.9f, %.3e) N m, force %.9f N\n",
      lags, q[10], moment.x(), moment.y(), moment.z(), force.z());
  EXPECT_NEAR(moment.y(), -torque, 1e-8 * torque);
  EXPECT_LT(std::abs(moment.x()) + std::abs(moment.z()), 1e-8 * torque);
  EXPECT_NEAR(force.z(), system.body(1).mass * g, 1e-8 * g);
  EXPECT_GT(std::abs(q[10]), 1e-6);  // it did tilt
}

}  // namespace
}  // namespace tailor::rigid::rigid_load_term_test
