// NewtonOptions::reuse_factorization: a sequence of warm-started solves with slowly changing
// moduli (as an optimizer makes them) reaches the same equilibria as Newton with a fresh
// factorization every iteration (the reference), with fewer factorizations; a large change
// makes CG fail and falls back to factorizing. FactorReuse::automatic: the flop count decides
// (a small bar does not pay, so it factorizes as without reuse), and where CG is allowed it does
// not slow Newton on a large deflection (the reference: Newton without reuse).
#include <gtest/gtest.h>

#include <cstdio>

#include "../../support/fem_fixtures.hpp"
#include "forward/fem/loads.hpp"
#include "forward/mesh/generate.hpp"
#include "forward/solve/newton.hpp"

namespace tailor::newton_reuse_test {
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
  o.reuse_factorization = reuse ? FactorReuse::on : FactorReuse::off;
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

TEST(NewtonReuse, AutomaticFollowsTheFlopCount) {
  Bar bar;
  NewtonSolver off(bar.model, options(false));
  NewtonOptions automatic_options = options(false);
  automatic_options.reuse_factorization = FactorReuse::automatic;
  NewtonSolver automatic(bar.model, automatic_options);
  NewtonOptions free_options = automatic_options;  // the cost test always passes
  free_options.reuse_min_factor_over_solve = free_options.reuse_min_factor_flops_per_slot = 0.0;
  NewtonSolver free_reuse(bar.model, free_options);
  Vector y_off = bar.rest, y_automatic = bar.rest, y_free = bar.rest;
  int automatic_cg = 0, free_cg = 0;
  for (int k = 0; k < 4; ++k) {
    const Vector p = moduli(bar.mesh, k);
    off.options().reference_residual = automatic.options().reference_residual =
        free_reuse.options().reference_residual = bar.rest_residual(p);
    const NewtonResult a = off.solve(p, y_off);
    const NewtonResult b = automatic.solve(p, y_automatic);
    const NewtonResult c = free_reuse.solve(p, y_free);
    ASSERT_TRUE(a.converged() && b.converged() && c.converged()) << a.report() << b.report() << c.report();
    // A factorization of this small bar fails the cost rule (flops per back-solve and per
    // slot): no CG, the same iterates as without reuse.
    EXPECT_EQ(b.iterations, a.iterations);
    EXPECT_EQ(b.factorizations(), a.factorizations());
    EXPECT_EQ((y_automatic - y_off).lpNorm<Eigen::Infinity>(), 0.0) << "step " << k;
    EXPECT_LT((y_free - y_off).lpNorm<Eigen::Infinity>(), 1e-7 * (y_off - bar.rest).lpNorm<Eigen::Infinity>());
    for (const auto& it : b.history) automatic_cg += it.reused_factorization ? 1 : 0;
    for (const auto& it : c.history) free_cg += it.reused_factorization ? 1 : 0;
  }
  EXPECT_EQ(automatic_cg, 0);
  EXPECT_GT(free_cg, 2) << "with the cost test passing, the warm-started solves take CG steps";
}

// A plane-strain corotated cantilever 4 x 1 (8 x 2 cells) clamped at x = 0, bent far by a tip load.
struct BentCantilever {
  Mesh mesh = rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(4, 1), 8, 2);
  Model model{2 * mesh.num_vertices()};
  Vector rest, p;
  BentCantilever() {
    const int m = mesh.num_elements();
    model.parameter_layout().add("youngs_modulus", m);
    model.parameter_layout().add("poisson_ratio", m);
    model.add(elastic_term<2>(mesh, MaterialKind::corotated));
    Vector forces = Vector::Zero(2 * mesh.num_vertices());
    std::vector<int> fixed;
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (mesh.rest_positions(v, 0) < 1e-12) fixed.insert(fixed.end(), {2 * v, 2 * v + 1});
      if (mesh.rest_positions(v, 0) > 4.0 - 1e-12) forces[2 * v + 1] = -5.0;
    }
    model.add(std::make_unique<ExternalForceTerm>(forces));
    model.set_elimination(Elimination::dirichlet(fixed, rest_state(mesh)));
    rest = model.elimination().restrict_state(rest_state(mesh));
    p.resize(2 * m);
    p.head(m).setConstant(1000.0);
    p.tail(m).setConstant(0.3);
  }
};

TEST(NewtonReuse, AutomaticKeepsConvergenceOnALargeDeflection) {
  BentCantilever bar;
  NewtonOptions off_options;
  off_options.reuse_factorization = FactorReuse::off;
  NewtonOptions automatic_options = off_options;
  automatic_options.reuse_factorization = FactorReuse::automatic;
  automatic_options.reuse_min_factor_over_solve = automatic_options.reuse_min_factor_flops_per_slot = 0.0;
  NewtonOptions on_options = off_options;
  on_options.reuse_factorization = FactorReuse::on;
  NewtonSolver off(bar.model, off_options), automatic(bar.model, automatic_options), on(bar.model, on_options);
  Vector y_off = bar.rest, y_automatic = bar.rest, y_on = bar.rest;
  const NewtonResult a = off.solve(bar.p, y_off);
  const NewtonResult b = automatic.solve(bar.p, y_automatic);
  const NewtonResult c = on.solve(bar.p, y_on);
  int cg_steps = 0;
  for (const auto& it : b.history) cg_steps += it.reused_factorization ? 1 : 0;
  std::printf("bent cantilever: Newton iterations off %d, automatic %d (%d by CG), on %d (%s)\n", a.iterations,
              b.iterations, cg_steps, c.iterations, to_string(c.status).c_str());
  EXPECT_GT(cg_steps, 0) << b.report();
  ASSERT_TRUE(a.converged()) << a.report();
  ASSERT_TRUE(b.converged()) << b.report();
  const double deflection = (y_off - bar.rest).lpNorm<Eigen::Infinity>();
  ASSERT_GT(deflection, 0.5) << "a large deflection";
  EXPECT_LT((y_automatic - y_off).lpNorm<Eigen::Infinity>(), 1e-7 * deflection);
  // CG only where Newton converges (full steps that halve the residual): at most one more
  // iteration than factorizing every time.
  EXPECT_LE(b.iterations, a.iterations + 1) << "off:\n" << a.report() << "automatic:\n" << b.report();
  for (std::size_t k = 1; k < b.history.size(); ++k)
    if (b.history[k].reused_factorization) {
      EXPECT_EQ(b.history[k - 1].step_length, 1.0) << b.report();
      EXPECT_LE(b.history[k].residual, 0.5 * b.history[k - 1].residual) << b.report();
    }
}

}  // namespace
}  // namespace tailor::newton_reuse_test
