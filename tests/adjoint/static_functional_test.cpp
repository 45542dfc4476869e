// The static adjoint: Taylor tests of whole reduced functionals (rate >= 1.9) on linear and
// large-deformation Neo-Hookean scenes, direct mode against the adjoint, the residual form's
// Jacobian against differences, and the Taylor test's own ability to fail.
#include "adjoint/scaled_gradient.hpp"
#include "adjoint/static_functional.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "../support/fem_fixtures.hpp"
#include "../support/inverse_fixtures.hpp"
#include "../support/traction_bar.hpp"
#include "adjoint/taylor_test.hpp"
#include "forward/fem/loads.hpp"

namespace tailor::static_functional_test {
namespace {

using namespace tailor::testing;

// A clamped 3D bar (4 x 1 x 1) bent by an end traction; design: per-element log E.
using BarProblem = TractionBar;

TEST(StaticFunctional, TaylorTestLinearMaterial) {
  BarProblem bar(MaterialKind::linear, 20.0);
  StaticFunctional f = bar.functional(1e-6);
  const TaylorTestResult t = taylor_test(f, bar.z0());
  std::printf("linear bar, per-element log E:\n%s", t.table().c_str());
  EXPECT_TRUE(t.passed()) << t.table();
  EXPECT_GE(t.rate1, 1.9) << t.table();
  EXPECT_NEAR(t.rate0, 1.0, 0.2) << t.table();
}

TEST(StaticFunctional, TaylorTestNeoHookeanLargeDeformation) {
  BarProblem bar(MaterialKind::neo_hookean, 60.0);
  StaticFunctional f = bar.functional(1e-6);
  Vector g;
  f.value_and_gradient(bar.z0(), g);
  // Large deformation: the tip moves by a sizeable fraction of the bar length.
  double tip = 0.0;
  for (int d : bar.tip_dofs) tip = std::max(tip, std::abs(f.state()[d] - bar.rest[d]));
  EXPECT_GT(tip, 0.5);
  const TaylorTestResult t = taylor_test(f, bar.z0());
  std::printf("Neo-Hookean bar, tip displacement %.3f, per-element log E:\n%s", tip, t.table().c_str());
  EXPECT_TRUE(t.passed()) << t.table();
}

// With NewtonOptions::reuse_factorization the forward solves of the Taylor test's nearby designs
// take CG steps preconditioned by a factor of another design; the gradient must stay exact.
TEST(StaticFunctional, TaylorTestWithKeptFactorization) {
  BarProblem bar(MaterialKind::neo_hookean, 60.0);
  StaticFunctionalOptions options;
  options.newton.reuse_factorization = FactorReuse::on;
  StaticFunctional f = bar.functional(1e-6, options);
  const TaylorTestResult t = taylor_test(f, bar.z0());
  std::printf("Neo-Hookean bar, forward solves reusing factorizations:\n%s", t.table().c_str());
  EXPECT_TRUE(t.passed()) << t.table();
  f.value(bar.z0() + Vector::Constant(bar.z0().size(), 1e-3));
  bool reused = false;
  for (const auto& it : f.last_newton().history) reused = reused || it.reused_factorization;
  EXPECT_TRUE(reused) << f.last_newton().report();
}

TEST(StaticFunctional, AdjointSolveReusesNewtonWork) {
  BarProblem bar(MaterialKind::neo_hookean, 30.0);
  StaticFunctional f = bar.functional();
  Vector g;
  f.value_and_gradient(bar.z0(), g);
  EXPECT_EQ(f.last_hessian_solve(), HessianSolve::preconditioned_cg) << to_string(f.last_hessian_solve());
  EXPECT_LE(f.last_cg_iterations(), 10);
  EXPECT_EQ(f.counters().forward_solves, 1);
  EXPECT_EQ(f.counters().adjoint_solves, 1);
  // The same z is served from the cache.
  f.value(bar.z0());
  EXPECT_EQ(f.counters().forward_solves, 1);
}

TEST(StaticFunctional, WarmStartNextToTheEquilibriumConverges) {
  // A tiny design change leaves the warm start almost in equilibrium; the relative tolerance
  // must then refer to the residual at rest, not to the tiny initial one.
  BarProblem bar(MaterialKind::neo_hookean, 30.0);
  StaticFunctional f = bar.functional();
  const Vector z = bar.z0();
  f.value(z);
  const double cold_iterations = f.last_newton().iterations;
  const Vector dz = Vector::Constant(f.size(), 1e-9);
  EXPECT_NO_THROW(f.value(z + dz));
  EXPECT_TRUE(f.last_newton().converged()) << f.last_newton().report();
  EXPECT_LE(f.last_newton().iterations, 2);
  EXPECT_GT(cold_iterations, 2);
  EXPECT_EQ(f.counters().forward_solves, 2);  // no retry from rest was needed
}

TEST(StaticFunctional, DirectModeAgreesWithAdjoint) {
  BarProblem bar(MaterialKind::stvk, 20.0);
  StaticFunctional f = bar.functional(1e-3);
  const Vector z = bar.z0();
  Vector g;
  f.value_and_gradient(z, g);
  // Chain rule through dx/dz: dJ/dz = J_x dx/dz + J_p dp/dz.
  const Matrix dx = f.state_sensitivity(z);
  Vector r;
  Matrix jac;
  f.residuals(z, r, &jac);
  const Vector g_direct = jac.transpose() * r;
  EXPECT_LT((g - g_direct).norm(), 1e-8 * g.norm());
  EXPECT_EQ(dx.cols(), f.size());
  // The residual Jacobian against central differences along a direction.
  const Vector dz = Vector::LinSpaced(f.size(), -1.0, 1.0);
  const double h = 1e-6;
  Vector rp, rm;
  f.residuals(z + h * dz, rp, nullptr);
  f.residuals(z - h * dz, rm, nullptr);
  EXPECT_LT(((rp - rm) / (2 * h) - jac * dz).norm(), 1e-6 * (jac * dz).norm());
}

// The state products a caller chains through (Python's J.vjp / J.jvp): the JVP against central
// differences of the equilibrium, the VJP as its exact transpose, and the VJP with the
// objective's own dT/dx equal to the gradient (a least-squares target with no direct p term).
TEST(StaticFunctional, StateProductsAgreeWithDifferencesAndWithTheGradient) {
  BarProblem bar(MaterialKind::neo_hookean, 20.0);
  StaticFunctional f = bar.functional(0.0);  // T(x) only: no Tikhonov term in p
  const Vector z = bar.z0() + 0.1 * Vector::LinSpaced(f.size(), -1.0, 1.0);
  f.value(z);
  const Vector x = f.state();
  const Vector dz = Vector::LinSpaced(f.size(), 1.0, -0.5);
  const Vector jvp = f.state_jvp(z, dz);
  const double h = 1e-5;
  f.value(z + h * dz);
  const Vector xp = f.state();
  f.value(z - h * dz);
  const Vector xm = f.state();
  const Vector difference = (xp - xm) / (2 * h);
  EXPECT_GT(jvp.norm(), 0.0);
  EXPECT_LT((difference - jvp).norm(), 1e-6 * jvp.norm());
  // A wrong JVP (a tenth off) is seen by the same comparison.
  EXPECT_GT((difference - 1.1 * jvp).norm(), 1e-6 * jvp.norm());

  const Vector w = Vector::LinSpaced(x.size(), -2.0, 3.0);
  const Vector vjp = f.state_vjp(z, w);
  EXPECT_NEAR(vjp.dot(dz), w.dot(f.state_jvp(z, dz)), 1e-9 * std::abs(vjp.dot(dz)));

  Vector gradient;
  f.value_and_gradient(z, gradient);
  // dT/dx of the bar's tip target, T = 1/2 sum (x_k - t_k)^2 over the tip DOFs (as functional()).
  Vector jx = Vector::Zero(x.size());
  for (std::size_t k = 0; k < bar.tip_dofs.size(); ++k) {
    const int dof = bar.tip_dofs[k];
    jx[dof] = f.state()[dof] - (bar.rest[dof] + (k % 3 == 2 ? -0.3 : 0.05));
  }
  EXPECT_LT((f.state_vjp(z, jx) - gradient).norm(), 1e-10 * gradient.norm());
}

TEST(TaylorTest, DetectsAWrongGradient) {
  BarProblem bar(MaterialKind::linear, 20.0);
  StaticFunctional f = bar.functional();
  ScaledGradient bad(f, 1.2);  // a 20% error, e.g. a missing factor in one term
  const TaylorTestResult t = taylor_test(bad, bar.z0());
  EXPECT_EQ(t.status, TaylorStatus::failed) << t.table();
  EXPECT_LT(t.rate1, 1.5) << t.table();
}

// J(z) = 1/2 |z|^2 analytically, to check the test's own bookkeeping.
class Quadratic final : public ReducedFunctional {
 public:
  int size() const override { return 3; }
  double value(const Vector& z) override { return 0.5 * z.squaredNorm() + offset; }
  double value_and_gradient(const Vector& z, Vector& g) override {
    g = z;
    return value(z);
  }
  double offset = 0.0;
};

TEST(TaylorTest, VanishingDerivativeIsNotAPass) {
  Quadratic q;
  const TaylorTestResult t = taylor_test(q, Vector::Zero(3));  // gradient zero at the minimum
  EXPECT_EQ(t.status, TaylorStatus::vanishing) << t.table();
}

TEST(TaylorTest, SearchesPastRoundOffAndRefusesWhenNoStepIsClean) {
  // A large constant offset raises the noise floor of J. With 1e6 the search grows h until the
  // second-order remainder is resolvable while still asymptotic, and passes; with 1e10 no
  // step is both (the remainder must exceed ~2e-3 x 640 while staying below 0.1 h |dJ.dz|).
  Quadratic q;
  q.offset = 1e6;
  TaylorTestOptions options;
  options.initial_step = 1e-3;
  const TaylorTestResult grown = taylor_test(q, Vector::Constant(3, 1.0), options);
  EXPECT_TRUE(grown.passed()) << grown.table();
  EXPECT_GT(grown.step, options.initial_step) << grown.table();
  q.offset = 1e10;
  const TaylorTestResult t = taylor_test(q, Vector::Constant(3, 1.0), options);
  EXPECT_EQ(t.status, TaylorStatus::not_asymptotic) << t.table();
  EXPECT_FALSE(t.passed());
}

// J(z) = c . z: the second-order remainder is round-off at every step.
class Linear final : public ReducedFunctional {
 public:
  int size() const override { return 3; }
  double value(const Vector& z) override { return Eigen::Vector3d(1, -2, 3).dot(z); }
  double value_and_gradient(const Vector& z, Vector& g) override {
    g = Eigen::Vector3d(1, -2, 3);
    return value(z);
  }
};

TEST(TaylorTest, LinearFunctionalIsRoundOffNotAPass) {
  Linear l;
  const TaylorTestResult t = taylor_test(l, Vector::Constant(3, 1.0));
  EXPECT_EQ(t.status, TaylorStatus::round_off) << t.table();
}

TEST(TaylorTest, ExactQuadraticPassesInTheAsymptoticRegime) {
  Quadratic q;
  const TaylorTestResult t = taylor_test(q, Vector::Constant(3, 1.0));
  EXPECT_TRUE(t.passed()) << t.table();
  EXPECT_NEAR(t.rate1, 2.0, 0.05);
  EXPECT_NEAR(t.rate0, 1.0, 0.1);
  for (const TaylorRow& row : t.rows) {
    if (!row.judged) continue;
    EXPECT_LE(row.remainder1, 0.1 * row.step * std::abs(t.directional_derivative)) << t.table();
  }
}

}  // namespace
}  // namespace tailor::static_functional_test

namespace tailor::static_functional_test {
namespace {

// A test-local objective with second derivatives: the DOF target objective is quadratic in x
// and p, so J_xx = I on the DOFs, J_pp = c I on the head.
TEST(StaticFunctional, HessianVectorProductPassesTaylorTestOnTheGradient) {
  for (MaterialKind kind : {MaterialKind::linear, MaterialKind::neo_hookean}) {
    BarProblem bar(kind, kind == MaterialKind::linear ? 20.0 : 40.0);
    StaticFunctional f = bar.functional(1e-4);
    ASSERT_TRUE(f.has_hessian_vector());
    const TaylorTestResult t = taylor_test_hessian(f, bar.z0());
    std::printf("Hessian-vector Taylor test (%s):\n%s", to_string(kind).c_str(), t.table().c_str());
    EXPECT_TRUE(t.passed()) << t.table();
  }
}

}  // namespace
}  // namespace tailor::static_functional_test

#include "objectives/target_positions.hpp"
#include "objectives/target_reaction_forces.hpp"
#include "objectives/weighted_sum.hpp"

namespace tailor::static_functional_test {
namespace {

// Handle displacements as design variables: the tip of a clamped Neo-Hookean bar is a handle
// whose prescribed displacement (x = x0 + D p + S y) is designed together with log E, to
// reach a target reaction force at the handle and target positions along the bar.
TEST(StaticFunctional, PrescribedHandleDisplacementsAsParameters) {
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(4, 1, 1), 4, 1, 1);
  const int m = mesh.num_elements();
  Model model(3 * mesh.num_vertices());
  model.parameter_layout().add("youngs_modulus", m);
  model.parameter_layout().add("poisson_ratio", m);
  model.add(elastic_term<3>(mesh, MaterialKind::neo_hookean));
  const Vector rest = rest_state(mesh);
  std::vector<int> fixed, handle_dofs, middle;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const double x = mesh.rest_positions(v, 0);
    if (x < 1e-9 || x > 4 - 1e-9)
      for (int k = 0; k < 3; ++k) fixed.push_back(3 * v + k);
    if (x > 4 - 1e-9)
      for (int k = 0; k < 3; ++k) handle_dofs.push_back(3 * v + k);
    if (std::abs(x - 2) < 1e-9) middle.push_back(v);
  }
  model.set_elimination(Elimination::dirichlet(fixed, rest));
  const int handle = model.add_prescribed_displacements("handle_displacement", handle_dofs);
  ASSERT_EQ(handle, 2 * m);
  EXPECT_THROW(model.add_prescribed_displacements("free", {3 * middle[0]}), std::invalid_argument);

  Vector base = heterogeneous_parameters(mesh, 1000.0, 0.3);
  base.conservativeResize(model.parameter_layout().size());
  base.tail(handle_dofs.size()).setZero();
  const auto map = embed_blocks(base, {{0, exp_map(m)}, {handle, identity_map(static_cast<int>(handle_dofs.size()))}});
  Matrix u(middle.size(), 3);
  u.rowwise() = Eigen::RowVector3d(0.02, 0.05, -0.3);
  auto positions = std::make_shared<TargetPositions>(TargetPositions::displacements(mesh, middle, u));
  auto force = std::make_shared<TargetReactionForces>(*model.terms()[0], model.num_dofs(), 3, handle_dofs,
                                                      TargetReactionForces::Aggregation::total, Eigen::Vector3d(5, 10, -40));
  auto objective = std::make_shared<WeightedSum>(std::vector<ObjectivePtr>{positions, force}, std::vector<double>{1.0, 1e-3});
  StaticFunctional f(model, map, objective, model.elimination().restrict_state(rest));

  Vector z(m + handle_dofs.size());
  z.head(m) = base.head(m).array().log().matrix();
  for (std::size_t k = 0; k < handle_dofs.size(); ++k) z[m + k] = (k % 3 == 2) ? -0.8 : 0.1;  // tip pushed down
  const TaylorTestResult t = taylor_test(f, z);
  std::printf("handle displacements + log E:\n%s", t.table().c_str());
  EXPECT_TRUE(t.passed()) << t.table();
  // The tip really sits where the parameters put it.
  f.value(z);
  for (std::size_t k = 0; k < handle_dofs.size(); ++k)
    EXPECT_NEAR(f.state()[handle_dofs[k]], rest[handle_dofs[k]] + z[m + k], 1e-14);

  // Second order with an objective that has second derivatives.
  StaticFunctional g(model, map, positions, model.elimination().restrict_state(rest));
  const TaylorTestResult th = taylor_test_hessian(g, z);
  EXPECT_TRUE(th.passed()) << th.table();
}

}  // namespace
}  // namespace tailor::static_functional_test
