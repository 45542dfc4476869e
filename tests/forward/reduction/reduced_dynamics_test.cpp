// Reduced implicit dynamics against closed forms, and Taylor tests of its discrete adjoint.
#include "forward/reduction/reduced_dynamics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "adjoint/reduced_dynamics_functional.hpp"
#include "adjoint/taylor_test.hpp"
#include "forward/reduction/mass_orthonormal_basis.hpp"
#include "forward/reduction/modal_analysis.hpp"
#include "forward/reduction/modal_derivatives.hpp"
#include "forward/reduction/reduced_stvk.hpp"
#include "reduction_fixtures.hpp"

namespace tailor::reduced_dynamics_test {
namespace {

using namespace tailor::testing;

struct ReducedBeam {
  ElasticBody body;
  ModalAnalysis modes;
  Matrix basis;
  std::unique_ptr<ReducedStvk> reduced;
};

// A StVK cantilever 4 x 1 x 1 (E = 1000, rho = 1: first period about 3 s), reduced on its
// `count` lowest modes, plus their modal derivatives when asked.
ReducedBeam reduced_beam(int count, bool derivatives) {
  ReducedBeam b{
      elastic_body(Eigen::Vector3d(4, 1, 1), Eigen::Vector3i(8, 2, 2), MaterialKind::stvk, true), {}, {}, {}};
  ModalAnalysisOptions options;
  options.count = count;
  b.modes = modal_analysis(*b.body.model, 3, b.body.rest, b.body.p, b.body.mass, options);
  b.basis = b.modes.modes;
  if (derivatives) {
    const Matrix psi = modal_derivatives(*b.body.model, b.body.rest, b.body.p, b.modes.modes);
    Matrix all(b.basis.rows(), count + psi.cols());
    all << b.modes.modes, psi;
    b.basis = mass_orthonormal_basis(all, b.body.mass);
  }
  b.reduced = std::make_unique<ReducedStvk>(*b.body.model, b.body.p, b.basis);
  return b;
}

// Undamped Newmark (average acceleration) on a linear oscillator q'' + w^2 q = 0 is the
// trapezoidal rule: q_n = q_0 cos(n theta), theta = 2 atan(w h / 2) (no amplitude error). At
// tiny amplitude the StVK modal coordinate is such an oscillator.
TEST(ReducedDynamics, UndampedNewmarkIsTheTrapezoidalOscillator) {
  const ReducedBeam b = reduced_beam(3, false);
  const double omega = std::sqrt(b.modes.eigenvalues[0]), h = 0.1;
  ReducedDynamicsOptions options;
  options.integrator = ReducedIntegrator::newmark;
  options.time_step = h;
  const ReducedDynamics dyn(*b.reduced, options);
  const double amplitude = 1e-6;
  const ReducedTrajectory t = dyn.simulate(amplitude * Vector::Unit(3, 0), Vector::Zero(3), 100);
  ASSERT_TRUE(t.converged) << t.message;
  const double theta = 2 * std::atan(omega * h / 2);
  double worst = 0;
  for (int n = 0; n <= 100; ++n)
    worst = std::max(worst,
                     std::abs(t.states[static_cast<std::size_t>(n)].q[0] - amplitude * std::cos(n * theta)));
  EXPECT_LT(worst, 1e-5 * amplitude);
}

// Rayleigh damping is diagonal in the modal basis, C = alpha I + beta Lambda: mode 1 decays
// as exp(-zeta w t) cos(w_d t), zeta = alpha / (2 w) + beta w / 2, w_d = w sqrt(1 - zeta^2)
// (closed form of the damped oscillator). Newmark's error is O((w h)^2).
TEST(ReducedDynamics, RayleighDampingMatchesTheDampedOscillator) {
  const ReducedBeam b = reduced_beam(3, false);
  const double omega = std::sqrt(b.modes.eigenvalues[0]);
  ReducedDynamicsOptions options;
  options.integrator = ReducedIntegrator::newmark;
  options.time_step = 2 * std::numbers::pi / omega / 200;
  options.rayleigh_mass = 0.1;
  options.rayleigh_stiffness = 0.01;
  const ReducedDynamics dyn(*b.reduced, options);
  const Matrix c = dyn.damping();
  EXPECT_LT((c - c.diagonal().asDiagonal().toDenseMatrix()).norm(), 1e-8 * c.norm());  // diagonal
  EXPECT_NEAR(c(0, 0), 0.1 + 0.01 * omega * omega, 1e-8);
  const double amplitude = 1e-6;
  const ReducedTrajectory t = dyn.simulate(amplitude * Vector::Unit(3, 0), Vector::Zero(3), 400);
  ASSERT_TRUE(t.converged);
  const double zeta = 0.1 / (2 * omega) + 0.01 * omega / 2, omega_d = omega * std::sqrt(1 - zeta * zeta);
  double worst = 0;
  for (int n = 0; n <= 400; ++n) {
    const double time = n * options.time_step;
    const double exact = amplitude * std::exp(-zeta * omega * time) *
                         (std::cos(omega_d * time) + zeta * omega / omega_d * std::sin(omega_d * time));
    worst = std::max(worst, std::abs(t.states[static_cast<std::size_t>(n)].q[0] - exact));
  }
  std::printf("zeta = %.4f, largest deviation from the closed form: %.2e of the amplitude\n", zeta,
              worst / amplitude);
  EXPECT_LT(worst, 5e-3 * amplitude);
}

// Taylor test of the discrete adjoint: 150 steps (about one period of the first mode), tip
// swinging by about a third of the beam length, z = [q0, v0, alpha, beta, s].
void taylor_check(ReducedIntegrator integrator) {
  const ReducedBeam b = reduced_beam(3, true);
  const int r = b.reduced->size();
  std::vector<int> tip;
  for (int v = 0; v < b.body.mesh.num_vertices(); ++v)
    if (b.body.mesh.rest_positions(v, 0) > 4 - 1e-9) tip.push_back(v);
  const Matrix rows = vertex_rows(b.basis, tip, 3);
  ReducedDynamicsOptions options;
  options.integrator = integrator;
  options.time_step = 0.02;
  const int steps = 150;
  // Initial velocity of the first mode with a tip speed of 3 length units per second.
  Vector v0 = Vector::Zero(r);
  v0[0] = 3.0 / rows.col(0).cwiseAbs().maxCoeff();
  const Vector z0 = ReducedDynamicsFunctional::pack(Vector::Zero(r), v0, 0.05, 0.005, 1.0);
  // Targets: the trajectory of other parameters.
  Vector z_true = z0;
  z_true[r] *= 1.3;
  z_true[2 * r + 2] = 1.2;
  ReducedDynamicsOptions true_options = options;
  true_options.rayleigh_mass = z_true[2 * r];
  true_options.rayleigh_stiffness = z_true[2 * r + 1];
  true_options.material_scale = z_true[2 * r + 2];
  const ReducedTrajectory truth =
      ReducedDynamics(*b.reduced, true_options).simulate(z_true.head(r), z_true.segment(r, r), steps);
  ASSERT_TRUE(truth.converged);
  const Matrix tip_path = vertex_displacements(truth, rows);
  std::vector<Vector> targets;
  for (Eigen::Index n = 0; n < tip_path.rows(); ++n) targets.push_back(tip_path.row(n).transpose());
  std::printf("%s: r = %d, largest tip displacement %.3f (beam length 4)\n", to_string(integrator).c_str(), r,
              tip_path.cwiseAbs().maxCoeff());
  EXPECT_GT(tip_path.cwiseAbs().maxCoeff(), 1.0);

  ReducedDynamicsFunctional functional(*b.reduced, options, Matrix(), Vector(), steps,
                                       std::make_shared<TrackedDisplacements>(rows, targets));
  TaylorTestOptions taylor;
  taylor.halvings = 5;
  const TaylorTestResult result = taylor_test(functional, z0, taylor);
  std::printf("%s", result.table().c_str());
  EXPECT_TRUE(result.passed()) << result.message;
  EXPECT_GE(result.rate1, 1.9);
}

TEST(ReducedDynamicsAdjoint, TaylorTestImplicitEuler) { taylor_check(ReducedIntegrator::implicit_euler); }
TEST(ReducedDynamicsAdjoint, TaylorTestNewmark) { taylor_check(ReducedIntegrator::newmark); }

// The chord Jacobian (once per step) converges to the same steps; one Newton step per time
// step (linearly implicit) is an approximation that stays close at this step size.
TEST(ReducedDynamics, ChordAndOneStepNewtonVariants) {
  const ReducedBeam b = reduced_beam(3, true);
  const int r = b.reduced->size();
  ReducedDynamicsOptions options;
  options.integrator = ReducedIntegrator::newmark;
  options.time_step = 0.02;
  Vector v0 = Vector::Zero(r);
  v0[0] = 3.0 / b.basis.cwiseAbs().col(0).maxCoeff();
  const ReducedTrajectory full = ReducedDynamics(*b.reduced, options).simulate(Vector::Zero(r), v0, 100);
  options.jacobian = ReducedJacobian::once_per_step;
  const ReducedTrajectory chord = ReducedDynamics(*b.reduced, options).simulate(Vector::Zero(r), v0, 100);
  options.jacobian = ReducedJacobian::every_iteration;
  options.max_newton_iterations = 1;
  options.accept_unconverged = true;
  const ReducedTrajectory one = ReducedDynamics(*b.reduced, options).simulate(Vector::Zero(r), v0, 100);
  ASSERT_TRUE(full.converged && chord.converged && one.converged);
  EXPECT_EQ(one.newton_iterations, 100);
  const double scale = full.states.back().q.norm();
  EXPECT_LT((chord.states.back().q - full.states.back().q).norm(), 1e-8 * scale);
  const double one_step_error = (one.states.back().q - full.states.back().q).norm() / scale;
  std::printf("one Newton step per time step: relative deviation after 100 steps %.2e\n", one_step_error);
  EXPECT_LT(one_step_error, 1e-3);
}

// The one-call driver: full-space initial conditions in the span of the basis are recovered
// exactly by the projection, and the vertex trajectory equals the rows of Phi times q.
TEST(ReducedDynamics, SimulatesVertexDisplacementsFromFullSpaceInitialConditions) {
  const ReducedBeam b = reduced_beam(3, true);
  const int r = b.reduced->size();
  Vector q0 = Vector::Zero(r), v0 = Vector::Zero(r);
  q0[1] = 0.1;
  v0[0] = 1.0;
  EXPECT_LT((project_to_basis(b.basis, b.body.mass, b.basis * q0) - q0).norm(), 1e-12);
  ReducedDynamicsOptions options;
  options.time_step = 0.02;
  const ReducedDynamics dyn(*b.reduced, options);
  const std::vector<int> vertices = {5, 17};
  const Matrix path =
      simulate_vertex_displacements(dyn, b.basis, b.body.mass, vertices, 3, b.basis * q0, b.basis * v0, 20);
  const ReducedTrajectory t = dyn.simulate(q0, v0, 20);
  ASSERT_EQ(path.rows(), 21);
  ASSERT_EQ(path.cols(), 6);
  EXPECT_LT((path.row(20).transpose() - vertex_rows(b.basis, vertices, 3) * t.states[20].q).norm(),
            1e-8 * path.row(20).norm());  // the projected initial conditions differ at round-off
  EXPECT_THROW(simulate_vertex_displacements(dyn, b.basis.leftCols(2), b.body.mass, vertices, 3, b.basis * q0,
                                             b.basis * v0, 2),
               std::invalid_argument);
}

TEST(ReducedDynamics, RejectsBadOptions) {
  const ReducedBeam b = reduced_beam(2, false);
  ReducedDynamicsOptions options;
  options.time_step = 0;
  EXPECT_THROW(ReducedDynamics(*b.reduced, options), std::invalid_argument);
  options.time_step = 0.1;
  options.rayleigh_mass = -1;
  EXPECT_THROW(ReducedDynamics(*b.reduced, options), std::invalid_argument);
  options.rayleigh_mass = 0;
  EXPECT_THROW(ReducedDynamics(*b.reduced, options, Matrix::Identity(3, 3)), std::invalid_argument);
  const ReducedDynamics dyn(*b.reduced, options);
  EXPECT_THROW(dyn.simulate(Vector::Zero(3), Vector::Zero(2), 1), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::reduced_dynamics_test
