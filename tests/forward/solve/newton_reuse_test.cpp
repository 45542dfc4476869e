// NewtonOptions::reuse_factorization: a sequence of warm-started solves with slowly changing
// moduli (as an optimizer makes them) reaches the same equilibria as Newton with a fresh
// factorization every iteration (the reference), with fewer factorizations; a large change
// makes CG fail and falls back to factorizing.
#include <gtest/gtest.h>

#include "../../support/fem_fixtures.hpp"
#include "forward/fem/loads.hpp"
#include "forward/solve/newton.hpp"

namespace tailor {
namespace {

using namespace tailor::testing;

// A Neo-Hookean bar 2 x 1 x 1 clamped at x = 0 and pulled and bent by nodal forces at x = 2.
struct Bar : ClampedBar {
  Bar() : ClampedBar(MaterialKind::neo_hookean, Eigen::Vector3i(6, 3, 3), Eigen::Vector3d(2.0, 0.0, -0.4)) {}
  // The residual at rest: the scale warm starts measure their tolerance against.
  double rest_residual(const Vector& p) const {
    return model.elimination().reduce(model.gradient(model.elimination().expand(rest), p)).norm();
  }
};

NewtonOptions options(bool reuse) {
  NewtonOptions o;
  o.hessian = NewtonHessian::adaptive;
  o.relative_tolerance = 1e-10;
  o.reuse_factorization = reuse;
  return o;
}

// Moduli of step k: the heterogeneous field, changed by about 1% per step as an optimizer would.
Vector moduli(const Mesh& mesh, int k) {
  Vector p = heterogeneous_parameters(mesh, 1e3, 0.3);
  const int m = mesh.num_elements();
  for (int e = 0; e < m; ++e) p[e] *= 1.0 + 0.01 * k * std::sin(0.37 * e);
  return p;
}

TEST(NewtonReuse, NearbySolvesMatchFreshFactorizationsWithFewerOfThem) {
  Bar bar;
  NewtonSolver fresh(bar.model, options(false)), reuse(bar.model, options(true));
  Vector y_fresh = bar.rest, y_reuse = bar.rest;
  int fresh_factorizations = 0, reuse_factorizations = 0, reused_steps = 0;
  for (int k = 0; k < 6; ++k) {
    const Vector p = moduli(bar.mesh, k);
    fresh.options().reference_residual = reuse.options().reference_residual = bar.rest_residual(p);
    const NewtonResult a = fresh.solve(p, y_fresh);
    const NewtonResult b = reuse.solve(p, y_reuse);
    ASSERT_TRUE(a.converged()) << a.report();
    ASSERT_TRUE(b.converged()) << b.report();
    EXPECT_LE(b.final_residual, 1e-10 * bar.rest_residual(p)) << b.report();
    // Both residuals are below 1e-10 of the load: the states agree to about that relative to the
    // displacement (the bar is well conditioned at this size).
    EXPECT_LT((y_reuse - y_fresh).lpNorm<Eigen::Infinity>(),
              1e-7 * (y_fresh - bar.rest).lpNorm<Eigen::Infinity>())
        << "step " << k;
    fresh_factorizations += a.factorizations();
    reuse_factorizations += b.factorizations();
    for (const auto& it : b.history) {
      reused_steps += it.reused_factorization ? 1 : 0;
      if (it.reused_factorization) {
        EXPECT_EQ(it.factorizations, 0);
        EXPECT_GT(it.cg_iterations, 0);
        EXPECT_LE(it.cg_iterations, options(true).reuse_max_cg_iterations + 1);
      }
    }
    for (const auto& it : a.history) EXPECT_FALSE(it.reused_factorization);
    if (k > 0) {
      // The first solve (from rest, no kept factor) must factorize; the later ones reuse.
      EXPECT_GT(b.history.front().cg_iterations, 0) << b.report();
    }
  }
  EXPECT_GT(reused_steps, 5);
  EXPECT_LT(2 * reuse_factorizations, fresh_factorizations)
      << "reuse " << reuse_factorizations << ", fresh " << fresh_factorizations;
  // The kept factor is of an exact, positive definite Hessian: an adjoint can precondition with it.
  EXPECT_TRUE(reuse.factorization_is_exact());
  EXPECT_FALSE(reuse.factorization().is_ldlt());
  EXPECT_EQ(reuse.assembled_mode(), HessianMode::exact);
}

TEST(NewtonReuse, LargeChangeFallsBackToFactorizing) {
  Bar bar;
  NewtonSolver fresh(bar.model, options(false)), reuse(bar.model, options(true));
  NewtonOptions& o = reuse.options();
  o.reuse_max_cg_iterations = 3;
  Vector y_reuse = bar.rest;
  const Vector p0 = moduli(bar.mesh, 0);
  o.reference_residual = bar.rest_residual(p0);
  ASSERT_TRUE(reuse.solve(p0, y_reuse).converged());
  // Ten times softer on half the bar: the kept factor is a poor preconditioner.
  Vector p1 = p0;
  for (int e = 0; e < bar.mesh.num_elements(); e += 2) p1[e] *= 0.1;
  o.reference_residual = fresh.options().reference_residual = bar.rest_residual(p1);
  Vector y_fresh = y_reuse;
  const NewtonResult b = reuse.solve(p1, y_reuse);
  const NewtonResult a = fresh.solve(p1, y_fresh);
  ASSERT_TRUE(a.converged()) << a.report();
  ASSERT_TRUE(b.converged()) << b.report();
  ASSERT_FALSE(b.history.empty());
  EXPECT_FALSE(b.history.front().reused_factorization) << b.report();
  EXPECT_GT(b.history.front().cg_iterations, 0);
  EXPECT_GE(b.history.front().factorizations, 1);
  EXPECT_LT((y_reuse - y_fresh).lpNorm<Eigen::Infinity>(),
            1e-7 * (y_fresh - bar.rest).lpNorm<Eigen::Infinity>());
  EXPECT_NE(b.report().find("factorizations"), std::string::npos) << b.report();
}

}  // namespace
}  // namespace tailor
