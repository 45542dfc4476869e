// StaticFunctional's curvature products and the factorizations they and the forward solves
// cost: Gauss-Newton products equal (dr/dz)^T (dr/dz) v from the residual Jacobian, Hessian-
// vector products equal differences of gradients; products at an evaluated design reuse the
// forward solve's factorization (two back-solves each, at most one factorization per design);
// and a forward solve at a new design factorizes once instead of running CG with the previous
// design's factor (NewtonOptions::reuse_across_parameters), so an optimization costs one
// factorization per design and its adjoint one back-solve.
#include <gtest/gtest.h>

#include <cstdio>

#include "../support/fem_fixtures.hpp"
#include "../support/traction_bar.hpp"
#include "adjoint/static_functional.hpp"
#include "optimizers/optimizer.hpp"

namespace tailor::curvature_products_test {
namespace {

using namespace tailor::testing;

// Per-element designs as an optimizer makes them: every element changes differently.
Vector design(const Vector& z0, int k) {
  Vector z = z0;
  for (Eigen::Index e = 0; e < z.size(); ++e) z[e] += 0.05 * k * std::sin(0.7 * static_cast<double>(e) + k);
  return z;
}

TEST(CurvatureProducts, GaussNewtonIsTheSquareOfTheResidualJacobian) {
  TractionBar bar(MaterialKind::stvk, 20.0);
  StaticFunctional f = bar.functional(1e-3);
  ASSERT_TRUE(f.has_gauss_newton_vector());
  const Vector z = bar.z0();
  Vector r;
  Matrix J;
  f.residuals(z, r, &J);
  for (int k = 0; k < 3; ++k) {
    const Vector v = Vector::Random(f.size());
    const Vector expected = J.transpose() * (J * v);
    const Vector gn = f.gauss_newton_vector(z, v);
    EXPECT_LT((gn - expected).norm(), 1e-9 * expected.norm()) << "direction " << k;
  }
}

TEST(CurvatureProducts, HessianVectorProductsMatchGradientDifferences) {
  TractionBar bar(MaterialKind::neo_hookean, 30.0);
  StaticFunctionalOptions options;
  options.newton.relative_tolerance = 1e-13;
  StaticFunctional f = bar.functional(1e-3, options);
  const Vector z = bar.z0();
  const Vector v = Vector::LinSpaced(f.size(), -1.0, 1.0);
  Vector g;
  f.value_and_gradient(z, g);
  const Vector hv = f.hessian_vector(z, v);
  const Vector hv_again = f.hessian_vector(z, v);  // from the kept adjoint and mixed block
  const double h = 1e-5;
  Vector gp, gm;
  f.value_and_gradient(z + h * v, gp);
  f.value_and_gradient(z - h * v, gm);
  const Vector difference = (gp - gm) / (2 * h);
  EXPECT_LT((hv - difference).norm(), 1e-5 * difference.norm());
  EXPECT_LT((hv_again - hv).norm(), 1e-12 * hv.norm());
}

// After an evaluation, products at the same design cost two back-solves each: none for a
// linear material (the forward solve's factor is the Hessian's), one factorization at the
// equilibrium for a nonlinear one (the forward solve's last factor is of the previous Newton
// iterate), then none.
TEST(CurvatureProducts, ProductsReuseTheFactorizationAtTheirDesign) {
  for (MaterialKind kind : {MaterialKind::linear, MaterialKind::neo_hookean}) {
    SCOPED_TRACE(kind == MaterialKind::linear ? "linear" : "Neo-Hookean");
    TractionBar bar(kind, 30.0);
    StaticFunctional f = bar.functional(1e-3);
    const Vector z = bar.z0();
    Vector g;
    f.value_and_gradient(z, g);
    const FunctionalCounters before = f.counters();
    EXPECT_GE(before.factorizations, 1);
    const Vector v = Vector::Random(f.size());
    f.gauss_newton_vector(z, v);
    const long first = f.counters().factorizations - before.factorizations;
    EXPECT_EQ(first, kind == MaterialKind::linear ? 0 : 1);
    for (int k = 0; k < 3; ++k) {
      f.hessian_vector(z, v);
      f.gauss_newton_vector(z, v);
    }
    const FunctionalCounters after = f.counters();
    EXPECT_EQ(after.factorizations - before.factorizations, first);
    EXPECT_EQ(after.back_solves - before.back_solves, 2 * 7);
    EXPECT_EQ(after.hessian_vectors - before.hessian_vectors, 7);
    EXPECT_EQ(after.forward_solves, before.forward_solves);
  }
}

// The reuse rule on an inverse run: with the cost test of FactorReuse::automatic passing (as on
// large meshes), a forward solve at a new design used to take CG steps with the previous
// design's factor and leave its adjoint a CG solve or a factorization; now it factorizes once
// and the adjoint back-solves with that factor.
TEST(ReuseRule, EachNewDesignCostsOneFactorizationAndTheAdjointOneBackSolve) {
  TractionBar bar(MaterialKind::linear, 20.0, Eigen::Vector3i(8, 2, 2));
  StaticFunctionalOptions options;
  options.newton.reuse_min_factor_over_solve = options.newton.reuse_min_factor_flops_per_slot = 0.0;
  StaticFunctionalOptions across = options;
  across.newton.reuse_across_parameters = true;
  StaticFunctional now = bar.functional(1e-3, options), before = bar.functional(1e-3, across);
  int cg_steps_before = 0;
  for (int k = 0; k < 5; ++k) {
    const Vector z = design(bar.z0(), k);
    Vector g_now, g_before;
    const FunctionalCounters c0 = now.counters();
    now.value_and_gradient(z, g_now);
    const FunctionalCounters c1 = now.counters();
    EXPECT_EQ(c1.factorizations - c0.factorizations, 1) << "design " << k;
    EXPECT_EQ(now.last_hessian_solve(), HessianSolve::reused_factorization) << "design " << k;
    for (const NewtonIteration& it : now.last_newton().history) EXPECT_FALSE(it.reused_factorization);
    // The step and the check of a linear solve, and the adjoint.
    EXPECT_LE(c1.back_solves - c0.back_solves, 3) << "design " << k;
    before.value_and_gradient(z, g_before);
    for (const NewtonIteration& it : before.last_newton().history) cg_steps_before += it.reused_factorization;
    EXPECT_LT((g_now - g_before).norm(), 1e-8 * g_now.norm()) << "design " << k;
  }
  EXPECT_GT(cg_steps_before, 0) << "reuse_across_parameters takes CG steps with the previous design's factor";
}

// The same through an optimizer: one factorization per forward solve, whatever the back-end asks.
TEST(ReuseRule, AnOptimizationFactorizesOncePerDesign) {
  TractionBar bar(MaterialKind::linear, 20.0, Eigen::Vector3i(8, 2, 2));
  StaticFunctionalOptions options;
  options.newton.reuse_min_factor_over_solve = options.newton.reuse_min_factor_flops_per_slot = 0.0;
  StaticFunctional f = bar.functional(1e-3, options);
  OptimizerOptions o;
  o.backend = OptimizerBackend::nlopt_lbfgs;
  o.max_iterations = 20;
  // Bounds keep E within 1e2..1e5 (p0 about 1e3): no trial so extreme that the forward solve
  // fails (its LL^T and LDL^T attempts would count two factorizations).
  const int n = f.size();
  const Bounds box{Vector::Constant(n, std::log(1e2)), Vector::Constant(n, std::log(1e5))};
  const OptimizerResult r = minimize(f, bar.z0(), box, {}, o);
  ASSERT_GT(r.counters.forward_solves, 10) << r.message;
  std::printf("L-BFGS, 20 iterations: %d forward solves, %ld factorizations, %ld back-solves\n",
              r.counters.forward_solves, r.counters.factorizations, r.counters.back_solves);
  EXPECT_EQ(r.failed_evaluations, 0);
  EXPECT_EQ(r.counters.factorizations, r.counters.forward_solves);
  EXPECT_LE(r.counters.back_solves, 2 * r.counters.forward_solves + r.counters.adjoint_solves);
}

}  // namespace
}  // namespace tailor::curvature_products_test
