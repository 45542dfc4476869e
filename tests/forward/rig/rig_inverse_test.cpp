// Inverse use of the rigged arm: the moving-rest-shape model on the generic time integrator
// reproduces the validated stepper (MovingRestDynamics), its two time-dependent terms pass the
// energy-term derivative checks, and the transient adjoint's gradient of a marker's trajectory
// objective in log Young's modulus per region passes the Taylor test (rate >= 1.9 after the
// rate-1 regime), while the same gradient 1% off fails it.
#include <gtest/gtest.h>

#include <cstdio>

#include "adjoint/derivative_check.hpp"
#include "adjoint/scaled_gradient.hpp"
#include "forward/fem/mass.hpp"
#include "problems/rig/rig_inverse.hpp"

namespace tailor::rig::rig_inverse_test {
namespace {

// A small arm (8 x 2 x 2 cells, 384 tets) flexing its elbow to -1.2 rad in 0.3 s under gravity,
// with Rayleigh mass damping: every term of the model is active.
RigSceneSpec small_arm_scene() {
  RigSceneSpec spec;
  spec.name = "small_arm";
  spec.arm.cells_along = 8;
  spec.arm.cells_across = 2;
  spec.arm.youngs_modulus = 1e6;
  const TwoBoneArm arm = two_bone_arm(spec.arm);
  spec.bones = arm.bones;
  spec.weights = arm.weights;
  spec.key_times = {0.0, 0.3};
  spec.key_poses = {Vector::Zero(2), Eigen::Vector2d(0.1, -1.2)};
  spec.dynamics.time_step = 0.01;
  spec.dynamics.rayleigh_mass = 1.0;
  spec.gravity = Eigen::Vector3d(0.0, -9.81, 0.0);
  spec.duration = 0.3;
  spec.marker = Eigen::Vector3d(4.0, -0.25, 0.0);  // the forearm's tip, bottom edge
  return spec;
}

TEST(RigInverse, ModelOnTheTimeIntegratorEqualsTheMovingRestStepper) {
  const RigSceneSpec spec = small_arm_scene();
  const std::unique_ptr<RigMarkerInverse> inv = rig_marker_inverse(spec, 20, Eigen::Vector3d::Ones());
  RiggedBody body = inv->arm.body;
  const MovingRestDynamics reference(*inv->rig, body, spec.dynamics);
  MovingRestState s = reference.initial_state(), next;
  const int n = 3 * body.mesh.num_vertices();
  DynamicState state = inv->integrator->initial_state(Vector::Zero(n), Vector::Zero(n), inv->model.parameters);
  double largest = 0.0;
  for (int k = 1; k <= 20; ++k) {
    int iterations = 0;
    std::string message;
    ASSERT_TRUE(reference.step(*inv->trajectory, s, next, iterations, message)) << message;
    s = next;
    ASSERT_TRUE(inv->integrator->step(state, inv->model.parameters).converged());
    largest = std::max(largest, s.u.norm());
    EXPECT_LT((state.x - s.u).norm(), 1e-7 * s.u.norm()) << "step " << k;
    EXPECT_LT((state.v - s.v).norm(), 1e-6 * s.v.norm()) << "step " << k;
  }
  EXPECT_GT(largest, 1e-3);  // the motion does deform the arm
}

TEST(RigInverse, TimeDependentTermsPassTheDerivativeChecks) {
  const RigSceneSpec spec = small_arm_scene();
  const std::unique_ptr<RigMarkerInverse> inv = rig_marker_inverse(spec, 1, Eigen::Vector3d::Ones());
  const int n = 3 * inv->arm.body.mesh.num_vertices();
  Vector p = inv->model.parameters;
  const Vector noise = Vector::Random(p.size());
  for (int i = 0; i < p.size(); ++i) p[i] *= 1.0 + 0.2 * noise[i];
  const Vector u = 0.02 * Vector::Random(n);
  inv->model.elastic->set_time(0.17);
  inv->model.load->set_time(0.17);
  const EnergyTermCheck elastic = check_energy_term(*inv->model.elastic, u, p);
  EXPECT_TRUE(elastic.passed()) << elastic.table();
  // The load is linear in u: its Hessian vanishes (never counted as passed), the rest must pass.
  const EnergyTermCheck load = check_energy_term(*inv->model.load, u, p);
  for (const DerivativeCheck& c : load.checks)
    EXPECT_TRUE(c.quantity == "hessian" ? c.vanishing : c.passed) << load.table();
  // Its gradient is -M(rho) (g - d2X/dt2) at the time set (the mass matrix assembled apart).
  const SparseMatrix mass = mass_matrix(inv->arm.body.mesh, p.segment(inv->model.density_offset, inv->arm.body.mesh.num_elements()),
                                        MassLumping::consistent);
  Vector g(n);
  for (int v = 0; v < n / 3; ++v) g.segment<3>(3 * v) = spec.gravity;
  const Vector expected = -(mass * (g - inv->rig->rest_shape_acceleration((*inv->trajectory)(0.17))));
  Vector gradient = Vector::Zero(n);
  inv->model.load->add_gradient(Vector::Zero(n), p, gradient);
  EXPECT_LT((gradient - expected).norm(), 1e-12 * expected.norm());
}

TEST(RigInverse, MarkerTrajectoryGradientPassesTheTaylorTestAndAWrongOneFails) {
  const RigSceneSpec spec = small_arm_scene();
  const std::unique_ptr<RigMarkerInverse> inv = rig_marker_inverse(spec, 0, Eigen::Vector3d(1.3, 0.7, 1.2));
  ASSERT_EQ(inv->steps, 30);
  const TaylorTestResult t = taylor_test(*inv->functional, inv->z0);
  std::printf("%s", t.table().c_str());
  EXPECT_TRUE(t.passed()) << t.message;
  EXPECT_NEAR(t.rate0, 1.0, 0.1);
  EXPECT_GE(t.rate1, 1.9);
  EXPECT_GT(t.value, 0.0);  // the measured motion differs from the current one
  ScaledGradient wrong(*inv->functional, 1.01);
  const TaylorTestResult bad = taylor_test(wrong, inv->z0);
  EXPECT_FALSE(bad.passed()) << "a gradient 1% off passes:\n" << bad.table();
}

}  // namespace
}  // namespace tailor::rig::rig_inverse_test
