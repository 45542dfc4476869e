// Dynamics on the moving rest shape, against references written apart from it:
//  - a rig translating with constant acceleration a == FEM on a fixed rest shape with body force
//    -rho a (to round-off), and its damped limit == the closed-form axial compression of a bar
//    under a uniform body force, u(L) = -rho a L^2 / (2 E) (nu = 0);
//  - a rig spinning at a constant rate == FEM in the rotating frame with centrifugal and
//    Coriolis forces (implicit Euler there; the two converge to each other at first order);
//  - an unloaded body following its rig (posed, at rest or moved kinematically) stays undeformed;
//  - pose-space reduced dynamics against the full space on the two-bone arm.
#include <gtest/gtest.h>

#include <Eigen/SparseLU>
#include <cmath>
#include <cstdlib>
#include <iostream>

#include "forward/fem/elastic_term.hpp"
#include "forward/fem/mass.hpp"
#include "forward/mesh/generate.hpp"
#include "forward/rig/pose_space_dynamics.hpp"
#include "forward/rig/two_bone_arm.hpp"

namespace tailor::rig::rig_dynamics_test {
namespace {

struct Bar {
  RiggedBody body;
  std::vector<Bone> bones;
  Matrix weights;
};

// [0, L] x [0, w]^2, clamped (fixed to the rig) at x = 0, one bone.
Bar bar(std::vector<BoneDof> dofs, MaterialKind material, double poisson, int cells) {
  Bar b;
  b.body.mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.0, 0.1, 0.1), cells, 1, 1);
  const int ne = b.body.mesh.num_elements();
  b.body.material = material;
  b.body.youngs_modulus = Vector::Constant(ne, 1e4);
  b.body.poisson_ratio = Vector::Constant(ne, poisson);
  b.body.density = Vector::Constant(ne, 100.0);
  for (int v = 0; v < b.body.mesh.num_vertices(); ++v)
    if (b.body.mesh.rest_positions(v, 0) < 1e-12) b.body.fixed_vertices.push_back(v);
  b.bones = {Bone{"bar", -1, Eigen::Vector3d::Zero(), std::move(dofs)}};
  b.weights = Matrix::Ones(b.body.mesh.num_vertices(), 1);
  return b;
}

std::vector<Vector> simulate(const MovingRestDynamics& dynamics, const PoseTrajectory& trajectory, int steps) {
  MovingRestState state = dynamics.initial_state(), next;
  std::vector<Vector> u{state.u};
  for (int s = 0; s < steps; ++s) {
    int iterations = 0;
    std::string message;
    EXPECT_TRUE(dynamics.step(trajectory, state, next, iterations, message)) << message;
    state = next;
    u.push_back(state.u);
  }
  return u;
}

TEST(MovingRestShape, ConstantAccelerationEqualsBodyForceAndTheClosedForm) {
  const std::vector<BoneDof> translations = {{BoneDofType::translation, Eigen::Vector3d::UnitX()},
                                             {BoneDofType::translation, Eigen::Vector3d::UnitY()},
                                             {BoneDofType::translation, Eigen::Vector3d::UnitZ()}};
  const Eigen::Vector3d accel(30.0, -20.0, 10.0);
  const PoseTrajectory moving([&](double t) { return PoseMotion{0.5 * t * t * accel, t * accel, accel}; });
  const PoseTrajectory still([](double) { return PoseMotion{Vector::Zero(3), Vector::Zero(3), Vector::Zero(3)}; });
  Bar moving_bar = bar(translations, MaterialKind::stvk, 0.3, 6);
  const Rig rig(moving_bar.bones, moving_bar.body.mesh.rest_positions, moving_bar.weights);
  MovingRestOptions options;
  options.time_step = 0.01;
  const MovingRestDynamics on_rig(rig, moving_bar.body, options);
  RiggedBody loaded = moving_bar.body;
  loaded.gravity = -accel;
  const MovingRestDynamics body_force(rig, loaded, options);
  const std::vector<Vector> a = simulate(on_rig, moving, 40), b = simulate(body_force, still, 40);
  double largest = 0.0, difference = 0.0;
  for (std::size_t s = 0; s < a.size(); ++s) {
    largest = std::max(largest, b[s].norm());
    difference = std::max(difference, (a[s] - b[s]).norm());
  }
  EXPECT_GT(largest, 1e-3);
  EXPECT_LT(difference, 1e-9 * largest);

  // Damped to rest along x: the axial bar under body force -rho a, nu = 0 (1D closed form).
  Bar axial = bar(translations, MaterialKind::linear, 0.0, 8);
  MovingRestOptions damped = options;
  damped.rayleigh_mass = 40.0;
  const Eigen::Vector3d along_x(10.0, 0.0, 0.0);
  const PoseTrajectory pulled([&](double t) { return PoseMotion{0.5 * t * t * along_x, t * along_x, along_x}; });
  const Rig axial_rig(axial.bones, axial.body.mesh.rest_positions, axial.weights);
  const std::vector<Vector> u = simulate(MovingRestDynamics(axial_rig, axial.body, damped), pulled, 300);
  const double closed_form = -100.0 * 10.0 * 1.0 / (2.0 * 1e4);
  double tip = 0.0;
  int tips = 0;
  for (int v = 0; v < axial.body.mesh.num_vertices(); ++v)
    if (axial.body.mesh.rest_positions(v, 0) > 1.0 - 1e-12) tip += u.back()[3 * v], ++tips;
  EXPECT_NEAR(tip / tips, closed_form, 0.02 * std::abs(closed_form));
}

// Implicit Euler on the body-frame displacement w (x = R(t) (Xbar + w)) with the rotating
// frame's fictitious forces: M (w'' + 2 Omega w' + Omega^2 (Xbar + w)) + f_int(Xbar + w) = 0,
// Omega = omega [e_z]x per vertex. Returns u = R w at the end (the world displacement from the
// rigged shape R Xbar).
Vector rotating_frame_fem(const Bar& b, double omega, double h, int steps, bool coriolis) {
  const Mesh& mesh = b.body.mesh;
  const int n = 3 * mesh.num_vertices(), ne = mesh.num_elements();
  const ElasticTerm<3> elastic(mesh, make_material<3>(b.body.material), 0, ne);
  Vector params(2 * ne);
  params << b.body.youngs_modulus, b.body.poisson_ratio;
  const SparseMatrix mass = mass_matrix(mesh, b.body.density, MassLumping::consistent);
  Triplets t;
  for (int v = 0; v < mesh.num_vertices(); ++v) t.emplace_back(3 * v, 3 * v + 1, -omega), t.emplace_back(3 * v + 1, 3 * v, omega);
  SparseMatrix spin(n, n);
  spin.setFromTriplets(t.begin(), t.end());
  const SparseMatrix spin2 = spin * spin;
  Vector rest(n);
  for (int v = 0; v < mesh.num_vertices(); ++v) rest.segment<3>(3 * v) = mesh.rest_positions.row(v).transpose();
  std::vector<char> fixed(static_cast<std::size_t>(n), 0);
  for (int v : b.body.fixed_vertices)
    for (int c = 0; c < 3; ++c) fixed[static_cast<std::size_t>(3 * v + c)] = 1;
  Vector w = Vector::Zero(n), vel = Vector::Zero(n);
  const double cor = coriolis ? 2.0 : 0.0;
  for (int s = 0; s < steps; ++s) {
    Vector w1 = w;
    for (int it = 0; it < 30; ++it) {
      const Vector v1 = (w1 - w) / h;
      Vector r = mass * ((v1 - vel) / h + cor * (spin * v1) + spin2 * (rest + w1));
      elastic.add_gradient(rest + w1, params, r);
      for (int i = 0; i < n; ++i)
        if (fixed[static_cast<std::size_t>(i)]) r[i] = 0.0;
      if (r.norm() < 1e-11 * (1.0 + (mass * (rest)).norm())) break;
      SparseMatrix j = SparseMatrix(mass * (1.0 / (h * h))) + SparseMatrix(cor / h * (mass * spin)) +
                       SparseMatrix(mass * spin2) + elastic.hessian(rest + w1, params, HessianMode::exact);
      for (int col = 0; col < n; ++col)
        for (SparseMatrix::InnerIterator e(j, col); e; ++e)
          if (fixed[static_cast<std::size_t>(e.row())] || fixed[static_cast<std::size_t>(e.col())])
            e.valueRef() = e.row() == e.col() ? 1.0 : 0.0;
      Eigen::SparseLU<SparseMatrix> lu(j);
      w1 -= lu.solve(r);
    }
    vel = (w1 - w) / h;
    w = w1;
  }
  const double angle = omega * h * steps, c = std::cos(angle), sn = std::sin(angle);
  Vector u(n);
  for (int v = 0; v < n / 3; ++v)
    u.segment<3>(3 * v) << c * w[3 * v] - sn * w[3 * v + 1], sn * w[3 * v] + c * w[3 * v + 1], w[3 * v + 2];
  return u;
}

TEST(MovingRestShape, SpinningRigMatchesRotatingFrameFemWithCoriolis) {
  const Bar b = bar({{BoneDofType::rotation, Eigen::Vector3d::UnitZ()}}, MaterialKind::stvk, 0.3, 6);
  const Rig rig(b.bones, b.body.mesh.rest_positions, b.weights);
  const double omega = 4.0, end = 0.4;
  const PoseTrajectory spin([&](double t) {
    return PoseMotion{Vector::Constant(1, omega * t), Vector::Constant(1, omega), Vector::Zero(1)};
  });
  double previous = 0.0;
  for (int refine : {1, 2}) {
    const double h = 0.01 / refine;
    const int steps = static_cast<int>(std::lround(end / h));
    MovingRestOptions options;
    options.time_step = h;
    const Vector on_rig = simulate(MovingRestDynamics(rig, b.body, options), spin, steps).back();
    const Vector reference = rotating_frame_fem(b, omega, h, steps, true);
    const double error = (on_rig - reference).norm() / reference.norm();
    EXPECT_GT(reference.norm(), 1e-3);
    if (refine == 1) {
      EXPECT_LT(error, 0.12);
      // Without the Coriolis force the rotating frame is far off: the comparison sees it.
      const Vector no_coriolis = rotating_frame_fem(b, omega, h, steps, false);
      EXPECT_GT((on_rig - no_coriolis).norm() / no_coriolis.norm(), 5 * error);
    } else {
      EXPECT_LT(error, 0.65 * previous);  // first-order convergence of two first-order schemes
    }
    std::cout << "spinning rig, h = " << h << ": relative difference to the rotating frame " << error << "\n";
    previous = error;
  }
}

TEST(MovingRestShape, UnloadedBodyFollowingItsRigStaysUndeformed) {
  TwoBoneArmOptions small;
  small.cells_along = 8;
  small.cells_across = 1;
  const TwoBoneArm arm = two_bone_arm(small);
  const Rig rig(arm.bones, arm.body.mesh.rest_positions, arm.weights);
  const Vector posed = Eigen::Vector2d(0.3, -1.0);
  ASSERT_GT((rig.rest_shape(posed) - rig.rest_shape(Vector::Zero(2))).norm(), 0.5);  // really posed
  MovingRestOptions options;
  options.time_step = 0.01;
  // Held in a bent pose: the skinned shape is the rest shape, nothing deforms.
  const PoseTrajectory held({0.0, 1.0}, {posed, posed});
  for (const Vector& u : simulate(MovingRestDynamics(rig, arm.body, options), held, 10)) EXPECT_LT(u.norm(), 1e-12);
  // Moved kinematically (no inertial forces): still undeformed.
  const PoseTrajectory bend({0.0, 0.2}, {Vector::Zero(2), posed});
  options.inertial_forces = false;
  for (const Vector& u : simulate(MovingRestDynamics(rig, arm.body, options), bend, 20)) EXPECT_LT(u.norm(), 1e-12);
  // With inertial forces the same motion makes the body jiggle (the check above can fail).
  options.inertial_forces = true;
  EXPECT_GT(simulate(MovingRestDynamics(rig, arm.body, options), bend, 20).back().norm(), 1e-3);
}

// With one example pose, a basis spanning every free DOF and the exact cubature (every element at
// weight 1), the reduced equations are the full-space ones in other coordinates: the two
// trajectories agree to the Newton tolerance. This checks the inertial projections, the
// cubature forces on the moving rest shape and the stepping together.
TEST(PoseSpaceDynamics, WholeSpaceBasisReproducesTheFullSpace) {
  TwoBoneArmOptions small;
  small.cells_along = 4;
  small.cells_across = 1;
  const TwoBoneArm arm = two_bone_arm(small);
  const Rig rig(arm.bones, arm.body.mesh.rest_positions, arm.weights);
  MovingRestOptions options;
  options.time_step = 0.01;
  options.rayleigh_mass = 1.0;
  options.newton_tolerance = 1e-12;
  const int free_dofs = static_cast<int>(rigged_free_dofs(arm.body).size());
  PoseSpaceOptions reduced;
  reduced.basis.linear_modes = free_dofs - 1;
  reduced.basis.derivative_modes = 0;
  reduced.basis.size = free_dofs;
  reduced.cubature.max_elements = arm.body.mesh.num_elements();
  reduced.cubature.tolerance = 1e-13;
  const PoseSpaceDynamics pose_space(rig, arm.body, {ExamplePose{Eigen::Vector2d(0.0, -0.5), Matrix()}}, reduced,
                                     options);
  EXPECT_LT(pose_space.precomputation().front().training_error, 1e-12);
  const PoseTrajectory bend({0.0, 0.3}, {Vector::Zero(2), Eigen::Vector2d(0.2, -1.2)});
  const MovingRestDynamics full(rig, arm.body, options);
  MovingRestState f = full.initial_state(), fn;
  ReducedRigState q = pose_space.initial_state(), qn;
  double largest = 0.0, difference = 0.0;
  for (int s = 0; s < 40; ++s) {
    int iterations = 0;
    std::string message;
    ASSERT_TRUE(full.step(bend, f, fn, iterations, message)) << message;
    ASSERT_TRUE(pose_space.step(bend, q, qn, iterations, message)) << message;
    f = fn, q = qn;
    largest = std::max(largest, f.u.norm());
    difference = std::max(difference, (pose_space.displacement(bend(q.time).p, q.q) - f.u).norm());
  }
  EXPECT_GT(largest, 1e-2);
  EXPECT_LT(difference, 1e-8 * largest);
}

// Three example poses of the elbow, bases blended in between: the trajectory error against the
// full space falls as r grows, and the static responses to the rig's own motion loads
// (K^-1 M dX/dp, K^-1 M d2X/dp2) are what makes a small basis accurate: without them r = 6 is
// several times further off.
TEST(PoseSpaceDynamics, ReducedFollowsTheFullSpaceOnTheArm) {
  TwoBoneArmOptions small;
  small.cells_along = 8;
  small.cells_across = 2;
  small.youngs_modulus = 1e6;
  const TwoBoneArm arm = two_bone_arm(small);
  const Rig rig(arm.bones, arm.body.mesh.rest_positions, arm.weights);
  MovingRestOptions options;
  options.time_step = 0.01;
  options.rayleigh_mass = 1.0;
  const PoseTrajectory bend({0.0, 0.3, 0.6}, {Vector::Zero(2), Eigen::Vector2d(0.0, -1.6), Eigen::Vector2d(0.0, -0.8)});
  const MovingRestDynamics full(rig, arm.body, options);
  std::vector<Vector> reference;
  MovingRestState f = full.initial_state(), fn;
  for (int s = 0; s < 60; ++s) {
    int iterations = 0;
    std::string message;
    ASSERT_TRUE(full.step(bend, f, fn, iterations, message)) << message;
    f = fn;
    reference.push_back(f.u);
  }
  std::vector<double> errors;
  for (const auto& [r, motion_responses] : {std::pair{6, true}, std::pair{24, true}, std::pair{6, false}}) {
    PoseSpaceOptions reduced;
    reduced.basis.motion_responses = motion_responses;
    reduced.basis.linear_modes = std::min(r, 10);
    reduced.basis.derivative_modes = 3;
    reduced.basis.size = r;
    reduced.cubature.max_elements = 80;
    std::vector<ExamplePose> examples;
    for (double elbow : {0.0, -0.8, -1.6}) examples.push_back({Eigen::Vector2d(0.0, elbow), Matrix()});
    const PoseSpaceDynamics pose_space(rig, arm.body, examples, reduced, options);
    ReducedRigState q = pose_space.initial_state(), qn;
    double error2 = 0.0, norm2 = 0.0;
    for (int s = 0; s < 60; ++s) {
      int iterations = 0;
      std::string message;
      ASSERT_TRUE(pose_space.step(bend, q, qn, iterations, message)) << message;
      q = qn;
      error2 += (pose_space.displacement(bend(q.time).p, q.q) - reference[static_cast<std::size_t>(s)]).squaredNorm();
      norm2 += reference[static_cast<std::size_t>(s)].squaredNorm();
    }
    EXPECT_GT(norm2, 1e-4);
    errors.push_back(std::sqrt(error2 / norm2));
    std::cout << "arm, r = " << r << (motion_responses ? "" : " without the motion responses") << ", "
              << pose_space.cubature_elements()
              << " cubature elements: trajectory error against the full space " << errors.back() << "\n";
  }
  EXPECT_LT(errors[0], 0.15);
  EXPECT_LT(errors[1], 0.8 * errors[0]);
  EXPECT_GT(errors[2], 3.0 * errors[0]);
}

}  // namespace
}  // namespace tailor::rig::rig_dynamics_test
