// The time-dependent adjoint: Taylor tests (rate >= 1.9) of trajectory objectives over 100
// steps of a Neo-Hookean cantilever swinging under gravity with Rayleigh damping, for every
// scheme, with design variables per-element log E, per-element log density, Rayleigh alpha
// and beta and the initial velocities; the same for reduction by projection (a modal basis
// through Elimination::general); checkpointing against storing every state; and derivative
// checks of the trajectory objectives.
#include "adjoint/transient_functional.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <random>
#include <iostream>

#include "../support/modal_fixtures.hpp"
#include "adjoint/derivative_check.hpp"
#include "adjoint/taylor_test.hpp"

namespace tailor::transient_functional_test {
namespace {

using namespace tailor::testing;

struct SwingProblem {
  Cantilever c;
  int m;
  ParameterizationPtr map;
  Vector z0, v0;
  std::shared_ptr<TrajectorySum> objective = std::make_shared<TrajectorySum>();
  int steps = 100;

  static CantileverOptions options() {
    CantileverOptions o;
    o.gravity = Eigen::Vector3d(
        0.0, -1.0, -4.0);  // static tip deflection ~1.5 (linear theory): large rotation of the end
    o.rayleigh = true, o.alpha = 0.05, o.beta = 2e-3;
    return o;
  }

  explicit SwingProblem(bool design_velocities) : c(options()), m(c.num_elements()) {
    const int n = c.model->num_dofs(), np = c.model->parameter_layout().size();
    Vector base = Vector::Zero(np + (design_velocities ? n : 0));
    base.head(np) = c.p;
    std::vector<ParameterBlock> blocks{
        {0, exp_map(m)}, {c.terms.density_offset, exp_map(m)}, {c.terms.alpha_offset, identity_map(2)}};
    if (design_velocities) blocks.push_back({np, identity_map(n)});
    map = embed_blocks(base, blocks);
    z0.resize(map->num_design());
    z0.head(m) = c.p.head(m).array().log().matrix();
    z0.segment(m, m) = c.p.segment(c.terms.density_offset, m).array().log().matrix();
    z0.segment(2 * m, 2) << c.p[c.terms.alpha_offset], c.p[c.terms.beta_offset];
    // A sideways initial velocity of the free end region (zero on the clamped face).
    v0 = Vector::Zero(n);
    for (int v = 0; v < c.mesh.num_vertices(); ++v) v0[3 * v + 1] = 0.3 * c.mesh.rest_positions(v, 0) / 4.0;
    if (design_velocities) z0.tail(n) = v0;
    // Tip position keyframes, a final tip velocity target and first-mode amplitudes.
    std::vector<Keyframe> frames;
    for (int s = 10; s <= steps; s += 10) {
      Matrix t(c.tip_vertices.size(), 3);
      for (std::size_t i = 0; i < c.tip_vertices.size(); ++i)
        t.row(i) = c.mesh.rest_positions.row(c.tip_vertices[i]) + Eigen::RowVector3d(0.0, 0.1, -0.5);
      frames.push_back({s, t, 1.0});
    }
    objective->add(
        std::make_shared<KeyframeTargets>(3, c.tip_vertices, TrajectoryQuantity::position, frames));
    objective->add(std::make_shared<KeyframeTargets>(
        3, c.tip_vertices, TrajectoryQuantity::velocity,
        std::vector<Keyframe>{{steps, Matrix::Zero(c.tip_vertices.size(), 3), 0.1}}));
    const CantileverModes modes = cantilever_modes(c, c.p, 1);
    std::vector<AmplitudeKeyframe> amplitudes;
    for (int s = 25; s <= steps; s += 25) amplitudes.push_back({s, Vector::Constant(1, 0.05), 1.0});
    objective->add(std::make_shared<ModeAmplitudes>(modes.shapes, modes.mass, c.rest, amplitudes), 10.0);
  }
};

TransientFunctionalOptions functional_options(bool design_velocities, int steps, int checkpoint = 0) {
  TransientFunctionalOptions o;
  o.steps = steps;
  o.design_initial_velocities = design_velocities;
  o.checkpoint_interval = checkpoint;
  return o;
}

TimeIntegratorOptions integrator_options(TimeScheme scheme) {
  TimeIntegratorOptions o;
  o.scheme = scheme;
  o.time_step = 0.03;  // ~60 steps per first-mode period; 100 steps ~ 1.6 periods
  o.newton.relative_tolerance = 1e-12;
  if (std::getenv("TAILOR_DEBUG")) o.newton.progress = &std::cout;
  return o;
}

class TransientTaylor : public ::testing::TestWithParam<TimeScheme> {};

TEST_P(TransientTaylor, NeoHookeanSwingOver100Steps) {
  SwingProblem problem(true);
  TimeIntegrator integrator(*problem.c.model, integrator_options(GetParam()));
  TransientFunctional f(integrator, problem.map, problem.objective, problem.c.rest, problem.v0,
                        functional_options(true, problem.steps));
  Vector g;
  f.value_and_gradient(problem.z0, g);
  double tip = 0.0;
  for (const DynamicState& s : f.stored_states())
    for (int v : problem.c.tip_vertices) tip = std::max(tip, (s.x - problem.c.rest).segment(3 * v, 3).norm());
  EXPECT_GT(tip, 0.5);  // large deformation
  const TransientStatistics st = f.statistics();
  const TaylorTestResult t = taylor_test(f, problem.z0);
  std::printf(
      "%s: max tip displacement %.3f, forward %.3f s (%d Newton iterations), adjoint %.3f s (%.2f of "
      "forward; %d "
      "factorizations, %d CG solves)\n%s",
      to_string(GetParam()).c_str(), tip, st.forward_seconds, st.newton_iterations, st.adjoint_seconds,
      st.adjoint_seconds / st.forward_seconds, st.factorizations, st.cg_solves, t.table().c_str());
  EXPECT_TRUE(t.passed()) << t.table();
  EXPECT_GE(t.rate1, 1.9);
}

INSTANTIATE_TEST_SUITE_P(Schemes, TransientTaylor,
                         ::testing::Values(TimeScheme::implicit_euler, TimeScheme::newmark, TimeScheme::bdf2),
                         [](const auto& param_info) { return to_string(param_info.param); });

TEST(TransientFunctional, ReductionByProjection) {
  // u = Phi q with the 4 lowest modes: Elimination::general(X, Phi), a dense basis.
  SwingProblem problem(false);
  const CantileverModes modes = cantilever_modes(problem.c, problem.c.p, 4);
  problem.c.model->set_elimination(Elimination(problem.c.rest, modes.shapes.sparseView()));
  for (TimeScheme scheme : {TimeScheme::implicit_euler, TimeScheme::newmark}) {
    TimeIntegrator integrator(*problem.c.model, integrator_options(scheme));
    TransientFunctional f(integrator, problem.map, problem.objective, problem.c.rest,
                          Vector::Zero(problem.c.rest.size()), functional_options(false, problem.steps));
    Vector g;
    f.value_and_gradient(problem.z0, g);
    const TransientStatistics st = f.statistics();
    const TaylorTestResult t = taylor_test(f, problem.z0);
    std::printf("reduced (4 modes), %s: forward %.3f s (%d Newton iterations), adjoint %.3f s\n%s",
                to_string(scheme).c_str(), st.forward_seconds, st.newton_iterations, st.adjoint_seconds,
                t.table().c_str());
    EXPECT_EQ(f.stored_states().back().y.size(), 4);
    EXPECT_TRUE(t.passed()) << t.table();
  }
}

TEST(TransientFunctional, CheckpointingGivesTheSameGradient) {
  SwingProblem problem(true);
  TimeIntegrator integrator(*problem.c.model, integrator_options(TimeScheme::bdf2));
  TransientFunctional all(integrator, problem.map, problem.objective, problem.c.rest, problem.v0,
                          functional_options(true, problem.steps));
  Vector g_all, g_checkpointed;
  const double j_all = all.value_and_gradient(problem.z0, g_all);
  const TransientStatistics s_all = all.statistics();
  TransientFunctional checkpointed(integrator, problem.map, problem.objective, problem.c.rest, problem.v0,
                                   functional_options(true, problem.steps, 10));
  const double j_checkpointed = checkpointed.value_and_gradient(problem.z0, g_checkpointed);
  const TransientStatistics& s = checkpointed.statistics();
  std::printf(
      "store all: %d states (%.3f MB), adjoint %.3f s; every 10th: peak %d states (%.3f MB), %d recomputed "
      "steps (ratio %.2f), adjoint %.3f s\n",
      s_all.stored_states_peak, s_all.stored_megabytes_peak, s_all.adjoint_seconds, s.stored_states_peak,
      s.stored_megabytes_peak, s.recomputed_steps, s.recompute_ratio(), s.adjoint_seconds);
  EXPECT_EQ(j_all, j_checkpointed);
  EXPECT_LT((g_all - g_checkpointed).norm(), 1e-9 * g_all.norm());
  EXPECT_EQ(s_all.stored_states_peak, problem.steps + 1);
  EXPECT_LE(s.stored_states_peak, 10 + 11);
  EXPECT_EQ(s.recomputed_steps, 90);
  // The recomputed steps' Hessians are the ones the forward pass kept: neither counted twice.
  EXPECT_EQ(s.stored_hessians_used, s_all.stored_hessians_used);
  EXPECT_LE(s.stored_hessian_megabytes_peak, s_all.stored_hessian_megabytes_peak);
}

// The trajectory's vector-Jacobian product: objective_gradient with PositionCotangents W gives
// d/dz sum_n W_n . x_n, checked against central differences of the stored trajectory along a
// direction (with checkpointing, whose backward pass recomputes states); the functional's own
// value and gradient are unchanged by it.
TEST(TransientFunctional, ObjectiveGradientIsTheTrajectorysVectorJacobianProduct) {
  SwingProblem problem(false);
  const int steps = 20;
  TimeIntegrator integrator(*problem.c.model, integrator_options(TimeScheme::newmark));
  TransientFunctional f(integrator, problem.map, problem.objective, problem.c.rest, problem.v0,
                        functional_options(false, steps, 5));
  const int n = problem.c.model->num_dofs();
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  Matrix W(steps + 1, n);
  for (Eigen::Index i = 0; i < W.size(); ++i) W.data()[i] = normal(rng);
  Vector dz(problem.z0.size());
  for (Eigen::Index i = 0; i < dz.size(); ++i) dz[i] = normal(rng);
  dz.tail(2) *= 1e-3;  // alpha, beta
  const auto pairing = [&](const Vector& z) {  // sum_n W_n . x_n along a fresh forward pass
    TransientFunctional g(integrator, problem.map, std::make_shared<PositionCotangents>(W), problem.c.rest,
                          problem.v0, functional_options(false, steps));
    return g.value(z);
  };
  Vector g0;
  const double j0 = f.value_and_gradient(problem.z0, g0);
  const Vector vjp = f.objective_gradient(problem.z0, std::make_shared<PositionCotangents>(W));
  // h balances the difference's O(h^2) error against the states' Newton tolerance over 2h.
  const double h = 1e-4;
  const double difference = (pairing(problem.z0 + h * dz) - pairing(problem.z0 - h * dz)) / (2 * h);
  EXPECT_NEAR(vjp.dot(dz), difference, 1e-5 * std::abs(difference));
  // A vjp 1% off would fail the same check.
  EXPECT_GT(std::abs(1.01 * vjp.dot(dz) - difference), 1e-5 * std::abs(difference));
  Vector g1;
  EXPECT_EQ(f.value_and_gradient(problem.z0, g1), j0);
  EXPECT_LT((g1 - g0).norm(), 1e-12 * g0.norm());
  EXPECT_THROW(PositionCotangents(Matrix::Constant(2, n, std::nan(""))), std::invalid_argument);
}

// The trajectory's Jacobian-vector product (the forward tangent pass): against central
// differences of the stored states along a direction in log E, log density, Rayleigh's alpha
// and beta and the initial velocities, and as the transpose of the vector-Jacobian product,
// <vjp(W), dz> = <W, jvp(dz)>, for Newmark (the carried force) and BDF2 (two-step history),
// with and without checkpointing. A tangent without the damping parameters' mixed term (their
// entries of dz dropped) fails the difference check.
TEST(TransientFunctional, TrajectoryJvpMatchesDifferencesAndIsTheVjpsTranspose) {
  SwingProblem problem(true);
  const int steps = 12;
  const int n = problem.c.model->num_dofs();
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  Vector dz(problem.z0.size());
  for (Eigen::Index i = 0; i < dz.size(); ++i) dz[i] = normal(rng);
  dz.segment(2 * problem.m, 2) *= 1e-2;  // alpha, beta
  dz.tail(n) *= 0.1;                     // initial velocities
  Matrix W(steps + 1, n);
  for (Eigen::Index i = 0; i < W.size(); ++i) W.data()[i] = normal(rng);
  for (TimeScheme scheme : {TimeScheme::newmark, TimeScheme::bdf2}) {
    SCOPED_TRACE(to_string(scheme));
    TimeIntegrator integrator(*problem.c.model, integrator_options(scheme));
    TransientFunctional f(integrator, problem.map, problem.objective, problem.c.rest, problem.v0,
                          functional_options(true, steps));
    const Matrix jvp = f.trajectory_jvp(problem.z0, dz);
    ASSERT_EQ(jvp.rows(), steps + 1);
    const auto trajectory = [&](const Vector& z) {
      TransientFunctional g(integrator, problem.map, problem.objective, problem.c.rest, problem.v0,
                            functional_options(true, steps));
      g.value(z);
      Matrix x(steps + 1, n);
      for (int k = 0; k <= steps; ++k) x.row(k) = g.stored_states()[k].x.transpose();
      return x;
    };
    const double h = 1e-4;
    const Matrix difference = (trajectory(problem.z0 + h * dz) - trajectory(problem.z0 - h * dz)) / (2 * h);
    const double error = (jvp - difference).norm() / difference.norm();
    EXPECT_LT(error, 1e-5);
    Vector without_damping = dz;
    without_damping.segment(2 * problem.m, 2).setZero();
    const double error_without =
        (f.trajectory_jvp(problem.z0, without_damping) - difference).norm() / difference.norm();
    EXPECT_GT(error_without, 1e-5);
    const Vector vjp = f.objective_gradient(problem.z0, std::make_shared<PositionCotangents>(W));
    const double pairing = W.cwiseProduct(jvp).sum();
    EXPECT_NEAR(vjp.dot(dz), pairing, 1e-9 * std::abs(pairing));
    std::printf("%s: jvp against differences %.1e (without the damping terms %.1e), <vjp, dz> against "
                "<W, jvp> %.1e\n",
                to_string(scheme).c_str(), error, error_without, std::abs(vjp.dot(dz) - pairing) / std::abs(pairing));
    TransientFunctional checkpointed(integrator, problem.map, problem.objective, problem.c.rest, problem.v0,
                                     functional_options(true, steps, 4));
    EXPECT_LT((checkpointed.trajectory_jvp(problem.z0, dz) - jvp).norm(), 1e-8 * jvp.norm());
  }
  TimeIntegrator integrator(*problem.c.model, integrator_options(TimeScheme::implicit_euler));
  TransientFunctional f(integrator, problem.map, problem.objective, problem.c.rest, problem.v0,
                        functional_options(true, steps));
  EXPECT_THROW(f.trajectory_jvp(problem.z0, Vector::Zero(3)), std::invalid_argument);
}

TEST(TransientFunctional, FactorizationReuseDoesNotChangeTheGradient) {
  SwingProblem problem(false);
  TimeIntegrator integrator(*problem.c.model, integrator_options(TimeScheme::newmark));
  TransientFunctionalOptions fresh_options = functional_options(false, 40);
  fresh_options.reuse_factorizations = false;
  TransientFunctional reuse(integrator, problem.map, problem.objective, problem.c.rest, problem.v0,
                            functional_options(false, 40));
  TransientFunctional fresh(integrator, problem.map, problem.objective, problem.c.rest, problem.v0,
                            fresh_options);
  Vector a, b;
  reuse.value_and_gradient(problem.z0, a);
  fresh.value_and_gradient(problem.z0, b);
  EXPECT_LT((a - b).norm(), 1e-9 * b.norm());
  EXPECT_LT(reuse.statistics().factorizations, fresh.statistics().factorizations);
  EXPECT_EQ(fresh.statistics().factorizations, 40);
}

TEST(TransientFunctional, StoredStepHessiansGiveTheSameGradient) {
  // The backward pass takes the forward pass's copies of the converged step Hessians instead of
  // assembling them again: the same matrices, so the same gradient to round-off, with no
  // assembly left in the backward pass of a Neo-Hookean swing.
  SwingProblem problem(false);
  const int steps = 30;
  TimeIntegrator integrator(*problem.c.model, integrator_options(TimeScheme::implicit_euler));
  TransientFunctionalOptions assembling = functional_options(false, steps);
  assembling.stored_hessian_megabytes = 0.0;
  TransientFunctional stored(integrator, problem.map, problem.objective, problem.c.rest, problem.v0,
                             functional_options(false, steps));
  TransientFunctional assembled(integrator, problem.map, problem.objective, problem.c.rest, problem.v0,
                                assembling);
  Vector a, b;
  stored.value_and_gradient(problem.z0, a);
  assembled.value_and_gradient(problem.z0, b);
  const TransientStatistics& s = stored.statistics();
  std::printf("stored Hessians: %d used, %d assembled, peak %.3f MB; |g_stored - g_assembled| / |g| = %.2e\n",
              s.stored_hessians_used, s.hessian_assemblies, s.stored_hessian_megabytes_peak,
              (a - b).norm() / b.norm());
  EXPECT_LT((a - b).norm(), 1e-13 * b.norm());
  EXPECT_EQ(s.stored_hessians_used + s.hessian_assemblies, steps);
  EXPECT_GT(s.stored_hessians_used, steps / 2);  // only projected (indefinite) steps are not kept
  EXPECT_GT(s.stored_hessian_megabytes_peak, 0.0);
  EXPECT_EQ(assembled.statistics().stored_hessians_used, 0);
  EXPECT_EQ(assembled.statistics().hessian_assemblies, steps);
}

TEST(TransientFunctional, KeptFactorsOnANeoHookeanSwingAreRefinedToTheFreshGradient) {
  // Factor reuse on (CG preconditioned by the nearest kept factor, stored Hessians) against off
  // (every backward step factorized afresh): the gradients agree to the linear tolerance. The
  // kept factors really are of other states: their plain solves miss by far more than the
  // agreement asked for here, so a stale factor used without CG's refinement would fail it.
  SwingProblem problem(false);
  const int steps = 30;
  for (TimeScheme scheme : {TimeScheme::implicit_euler, TimeScheme::newmark}) {
    TimeIntegrator integrator(*problem.c.model, integrator_options(scheme));
    TransientFunctionalOptions fresh_options = functional_options(false, steps);
    fresh_options.reuse_factorizations = false;
    TransientFunctional reuse(integrator, problem.map, problem.objective, problem.c.rest, problem.v0,
                              functional_options(false, steps));
    TransientFunctional fresh(integrator, problem.map, problem.objective, problem.c.rest, problem.v0,
                              fresh_options);
    Vector a, b;
    reuse.value_and_gradient(problem.z0, a);
    fresh.value_and_gradient(problem.z0, b);
    const TransientStatistics& s = reuse.statistics();
    const double difference = (a - b).norm() / b.norm();
    std::printf(
        "%s: reuse %d factorizations, %d CG solves (%d iterations), %d stored Hessians, largest plain-solve "
        "residual of a kept factor %.2e; fresh %d factorizations; relative difference %.2e\n",
        to_string(scheme).c_str(), s.factorizations, s.cg_solves, s.cg_iterations, s.stored_hessians_used,
        s.max_preconditioner_residual, fresh.statistics().factorizations, difference);
    EXPECT_LT(difference, 1e-9);
    EXPECT_GT(s.cg_solves, 0);
    EXPECT_LT(s.factorizations, steps / 2);
    EXPECT_GT(s.stored_hessians_used, 0);
    EXPECT_GT(s.max_preconditioner_residual, 1e3 * 1e-9);
    EXPECT_EQ(fresh.statistics().factorizations, steps);
    EXPECT_EQ(fresh.statistics().stored_hessians_used, 0);
  }
}

TEST(TransientFunctional, TaylorTestWithKeptFactorsAndStoredHessians) {
  // Neo-Hookean swing with large rotations, reuse active (counts checked): the first-order
  // remainder falls at rate 1, the second-order one at rate >= 1.9.
  SwingProblem problem(false);
  const int steps = 30;
  TimeIntegrator integrator(*problem.c.model, integrator_options(TimeScheme::newmark));
  TransientFunctional f(integrator, problem.map, problem.objective, problem.c.rest, problem.v0,
                        functional_options(false, steps));
  Vector g;
  f.value_and_gradient(problem.z0, g);
  const TransientStatistics st = f.statistics();
  EXPECT_GT(st.cg_solves, 0);
  EXPECT_GT(st.stored_hessians_used, 0);
  // Along a random direction and along the gradient in the variables z_i / s_i, s_i =
  // max(|z_i|, 0.01) (a scaled descent direction, each entry at most s_i): a random direction
  // weighs the two Rayleigh coefficients little against the per-element entries.
  const Vector scale = problem.z0.cwiseAbs().cwiseMax(1e-2);
  const Vector descent = scale.cwiseProduct(scale).cwiseProduct(g);
  TaylorTestOptions along_gradient;
  along_gradient.direction = descent / descent.cwiseQuotient(scale).lpNorm<Eigen::Infinity>();
  for (const TaylorTestOptions& options : {TaylorTestOptions{}, along_gradient}) {
    const TaylorTestResult t = taylor_test(f, problem.z0, options);
    std::printf("reuse: %d CG solves, %d factorizations, %d stored Hessians\n%s", st.cg_solves,
                st.factorizations, st.stored_hessians_used, t.table().c_str());
    EXPECT_TRUE(t.passed()) << t.table();
    EXPECT_NEAR(t.rate0, 1.0, 0.1);
    EXPECT_GE(t.rate1, 1.9);
  }
}

TEST(TransientFunctional, ConstantHessianIsSolvedWithTheForwardFactor) {
  // Linear material, inertia and Rayleigh damping: the step Hessian is constant, and every
  // backward step is one back-solve with Newton's kept factor, for both one-step schemes
  // (Newmark's start switches the coefficients to those of g_0 and back). Taylor test as well.
  CantileverOptions o = SwingProblem::options();
  o.material = MaterialKind::linear;
  o.youngs_modulus = 1e4;  // small displacements against the length
  Cantilever c(o);
  const int m = c.num_elements(), steps = 30;
  auto map = embed_blocks(c.p, {{0, exp_map(m)}, {c.terms.alpha_offset, identity_map(2)}});
  Vector z0(m + 2);
  z0.head(m) = c.p.head(m).array().log().matrix();
  z0.tail(2) << c.p[c.terms.alpha_offset], c.p[c.terms.beta_offset];
  std::vector<Keyframe> frames;
  for (int s = 10; s <= steps; s += 10) {
    Matrix t(c.tip_vertices.size(), 3);
    for (std::size_t i = 0; i < c.tip_vertices.size(); ++i)
      t.row(i) = c.mesh.rest_positions.row(c.tip_vertices[i]) + Eigen::RowVector3d(0.0, 0.01, -0.05);
    frames.push_back({s, t, 1.0});
  }
  auto objective = std::make_shared<KeyframeTargets>(3, c.tip_vertices, TrajectoryQuantity::position, frames);
  for (TimeScheme scheme : {TimeScheme::implicit_euler, TimeScheme::newmark}) {
    TimeIntegrator integrator(*c.model, integrator_options(scheme));
    TransientFunctional f(integrator, map, objective, c.rest, Vector::Zero(c.rest.size()),
                          functional_options(false, steps));
    Vector g;
    f.value_and_gradient(z0, g);
    const TransientStatistics st = f.statistics();
    EXPECT_EQ(st.kept_factor_solves, steps) << to_string(scheme);
    EXPECT_EQ(st.adjoint_numeric_factorizations, 0) << to_string(scheme);
    EXPECT_EQ(st.adjoint_back_solves, steps) << to_string(scheme);
    EXPECT_EQ(st.hessian_assemblies, 0) << to_string(scheme);
    EXPECT_LE(st.forward_factorizations, 1) << to_string(scheme);
    // From h = 1e-3: along this direction Newmark's second- and third-order terms cancel near
    // h = 5e-3 (the remainder's rate climbs 1.4, 1.8, 1.9, 1.95 as h halves from there).
    TaylorTestOptions taylor;
    taylor.initial_step = 1e-3;
    const TaylorTestResult t = taylor_test(f, z0, taylor);
    std::printf("linear, %s: forward %ld factorizations, %ld back-solves; adjoint %ld back-solves\n%s",
                to_string(scheme).c_str(), st.forward_factorizations, st.forward_back_solves,
                st.adjoint_back_solves, t.table().c_str());
    EXPECT_TRUE(t.passed()) << t.table();
  }
}

TEST(TransientFunctional, InitialPositionsAndVelocitiesAsDesign) {
  // Only the initial state is designed (P = [p; x_0; v_0], p fixed): exercises the adjoint of
  // the history at step 0, including Newmark's start g_0 = -dPi_0/dx(x_0) with damping.
  SwingProblem problem(false);
  const int n = problem.c.model->num_dofs(), np = problem.c.model->parameter_layout().size();
  Vector base(np + 2 * n);
  base << problem.c.p, problem.c.rest, problem.v0;
  const ParameterizationPtr map = embed_blocks(base, {{np, identity_map(2 * n)}});
  Vector z0(2 * n);
  z0 << problem.c.rest, problem.v0;
  for (TimeScheme scheme : {TimeScheme::newmark, TimeScheme::bdf2}) {
    TimeIntegrator integrator(*problem.c.model, integrator_options(scheme));
    TransientFunctionalOptions options = functional_options(true, 40);
    options.design_initial_positions = true;
    TransientFunctional f(integrator, map, problem.objective, problem.c.rest, problem.v0, options);
    TaylorTestOptions taylor;
    taylor.direction_floor = 0.05;
    taylor.initial_step = 2e-3;
    const TaylorTestResult t = taylor_test(f, z0, taylor);
    std::printf("initial state as design, %s:\n%s", to_string(scheme).c_str(), t.table().c_str());
    EXPECT_TRUE(t.passed()) << t.table();
  }
}

TEST(TransientFunctional, BadInputIsRejected) {
  SwingProblem problem(false);
  TimeIntegrator integrator(*problem.c.model, integrator_options(TimeScheme::newmark));
  // The parameterization does not cover the designed initial velocities.
  EXPECT_THROW(TransientFunctional(integrator, problem.map, problem.objective, problem.c.rest, problem.v0,
                                   functional_options(true, 10)),
               std::invalid_argument);
  EXPECT_THROW(TransientFunctional(integrator, problem.map, problem.objective, problem.c.rest,
                                   Vector::Zero(3), functional_options(false, 10)),
               std::invalid_argument);
  EXPECT_THROW(KeyframeTargets(3, {0}, TrajectoryQuantity::position, {{1, Matrix::Zero(2, 3), 1.0}}),
               std::invalid_argument);
  EXPECT_THROW(KeyframeTargets(3, {0}, TrajectoryQuantity::position,
                               {{1, Matrix::Zero(1, 3), 1.0}, {1, Matrix::Zero(1, 3), 1.0}}),
               std::invalid_argument);
}

// Derivative checks of the trajectory objectives (value against the gradient, in x, v and p).
TEST(TrajectoryObjectives, GradientsMatchDifferences) {
  SwingProblem problem(false);
  const Vector& p = problem.c.p;
  const Eigen::Index n = problem.c.rest.size();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto random = [&](Eigen::Index size) {
    Vector r(size);
    for (Eigen::Index i = 0; i < size; ++i) r[i] = u(rng);
    return r;
  };
  const Vector x = problem.c.rest + 0.3 * random(n), v = random(n), dx = random(n), dv = random(n);
  for (int step : {0, 50, 100}) {
    Vector gx = Vector::Zero(n), gv = Vector::Zero(n), gp = Vector::Zero(p.size());
    problem.objective->add_gradient(step, x, v, p, gx, gv, gp);
    const auto along = [&](double t) {
      return Vector::Constant(1, problem.objective->value(step, x + t * dx, v + t * dv, p));
    };
    const DerivativeCheck check = check_directional_derivative(
        "trajectory objective", along, Vector::Constant(1, gx.dot(dx) + gv.dot(dv)), {});
    if (step == 0) {
      EXPECT_TRUE(check.vanishing) << check.message;  // no keyframe at step 0
    } else {
      EXPECT_TRUE(check.passed) << "step " << step << ": " << check.message;
    }
    // A gradient off by 1e-4 relative is rejected.
    if (step == 100) {
      const DerivativeCheck bad = check_directional_derivative(
          "skewed", along, Vector::Constant(1, (1 + 1e-4) * (gx.dot(dx) + gv.dot(dv))), {});
      EXPECT_FALSE(bad.passed) << bad.message;
    }
  }
}

}  // namespace
}  // namespace tailor::transient_functional_test
