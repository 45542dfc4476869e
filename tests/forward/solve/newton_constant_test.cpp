// Constant Hessians and the round-off floor (forward/solve/newton.hpp).
//  - A linear elastic bar: Newton factorizes once per parameter vector; a second solve with
//    the same p uses the kept factor (no factorization), a new p factorizes again, and the
//    equilibria equal those of Newton without the kept factor.
//  - A kept-factor step of a constant Hessian is taken without evaluating the energy at the
//    trial point (the quadratic's decrease is exact), while a step whose length a term limits
//    is still searched.
//  - The floor: a tolerance below what floating point can reach ends at the floor within two
//    iterations after the solve (not at the iteration limit), as converged; a state already in
//    equilibrium to round-off (a sliver tet at rest) converges at iteration 0; a 1e15 contrast
//    of moduli in a linear problem ends after a few iterations as ill_conditioned, naming a
//    condition estimate, while a 1e9 contrast converges.
#include <gtest/gtest.h>

#include "../../support/fem_fixtures.hpp"
#include "forward/fem/loads.hpp"
#include "forward/solve/newton.hpp"

namespace tailor::newton_constant_test {
namespace {

using namespace tailor::testing;

// A bar 2 x 1 x 1 of the given material, clamped at x = 0, nodal forces at x = 2.
struct LinearBar : ClampedBar {
  explicit LinearBar(MaterialKind kind = MaterialKind::linear)
      : ClampedBar(kind, Eigen::Vector3i(8, 4, 4), Eigen::Vector3d(0.02, 0.0, -0.01)) {}
  Vector parameters(double scale) const { return heterogeneous_parameters(mesh, 100.0 * scale, 0.3); }
};

TEST(NewtonConstantHessian, OneFactorizationPerParameterVector) {
  LinearBar bar;
  ASSERT_TRUE(bar.model.hessian_is_constant());
  NewtonSolver newton(bar.model);
  const Vector p = bar.parameters(1.0);
  Vector y = bar.rest;
  const NewtonResult first = newton.solve(p, y);
  ASSERT_TRUE(first.converged()) << first.report();
  EXPECT_EQ(first.factorizations(), 1);
  EXPECT_LE(first.iterations, 2);
  // The adjoint's factorization at the equilibrium is the kept one.
  EXPECT_TRUE(newton.factorization_matches_hessian());

  // Same p, another start: no factorization at all.
  Vector y2 = bar.rest;
  const NewtonResult second = newton.solve(p, y2);
  ASSERT_TRUE(second.converged());
  EXPECT_EQ(second.factorizations(), 0);
  EXPECT_TRUE(second.history.front().kept_constant_factor);
  EXPECT_LT((y2 - y).norm(), 1e-12 * y.norm());

  // New p: one factorization again; the result equals Newton without the kept factor.
  const Vector q = bar.parameters(1.7);
  Vector yq = bar.rest;
  EXPECT_EQ(newton.solve(q, yq).factorizations(), 1);
  NewtonOptions plain;
  plain.keep_constant_factorization = false;
  NewtonSolver reference(bar.model, plain);
  Vector yr = bar.rest;
  const NewtonResult ref = reference.solve(q, yr);
  ASSERT_TRUE(ref.converged());
  EXPECT_GE(ref.factorizations(), 1);
  EXPECT_LT((yq - yr).norm(), 1e-9 * (yr - bar.rest).norm());
}

// Zero energy with a constant (empty) Hessian that counts the evaluations asking for the energy;
// max_step optionally limits every step.
class CountingTerm : public EnergyTerm {
 public:
  explicit CountingTerm(int* energy_evaluations, double max_step = 1.0)
      : evaluations_(energy_evaluations), max_(max_step) {}
  std::string name() const override { return "counting"; }
  void evaluate(const Vector&, const Vector&, const EnergyRequest& request) const override {
    if (request.value) ++*evaluations_;
  }
  bool hessian_is_constant() const override { return true; }
  double max_step(const Vector&, const Vector&) const override { return max_; }

 private:
  int* evaluations_;
  double max_;
};

TEST(NewtonConstantHessian, KeptFactorStepSkipsTheTrialEnergy) {
  for (const double limit : {1.0, 0.9}) {
    LinearBar bar;
    int energy_evaluations = 0;
    bar.model.add(std::make_unique<CountingTerm>(&energy_evaluations, limit));
    ASSERT_TRUE(bar.model.hessian_is_constant());
    NewtonSolver newton(bar.model);
    const Vector p = bar.parameters(1.0);
    Vector y = bar.rest;
    ASSERT_TRUE(newton.solve(p, y).converged());
    energy_evaluations = 0;
    Vector y2 = bar.rest;
    const NewtonResult kept = newton.solve(p, y2);  // every step with the kept factor
    ASSERT_TRUE(kept.converged()) << kept.report();
    ASSERT_EQ(kept.factorizations(), 0);
    // The counter counts every energy evaluation. Newton evaluates each iterate once (a line
    // search's accepted first trial, with its gradient, stands for the next iterate's).
    EXPECT_EQ(energy_evaluations, kept.iterations + 1);
    if (limit == 1.0) {
      for (const auto& it : kept.history) EXPECT_EQ(it.line_search_steps, 0);
      EXPECT_LT((y2 - y).norm(), 1e-12 * y.norm());
    } else {
      // A step limited by a term is line-searched: its trial energy is evaluated at 0.9.
      for (const auto& it : kept.history) EXPECT_EQ(it.step_length, 0.9);
    }
  }
}

TEST(NewtonConstantHessian, NonlinearMaterialIsNotConstant) {
  LinearBar bar(MaterialKind::neo_hookean);
  EXPECT_FALSE(bar.model.hessian_is_constant());
  NewtonSolver newton(bar.model);
  Vector y = bar.rest;
  const NewtonResult r = newton.solve(bar.parameters(1.0), y);
  ASSERT_TRUE(r.converged());
  EXPECT_EQ(r.factorizations(), r.iterations);  // one per step: nothing is kept
}

TEST(NewtonRoundOffFloor, UnreachableToleranceStopsAtTheFloor) {
  LinearBar bar;
  NewtonOptions options;
  options.relative_tolerance = 1e-18;           // far below what double precision can reach
  options.keep_constant_factorization = false;  // each iteration refactorizes, as before
  NewtonSolver newton(bar.model, options);
  Vector y = bar.rest;
  const NewtonResult r = newton.solve(bar.parameters(1.0), y);
  EXPECT_EQ(r.status, NewtonStatus::round_off_floor) << r.report();
  EXPECT_TRUE(r.converged());
  EXPECT_LE(r.iterations, 3);  // the solve, then at most two iterations to see the floor
  EXPECT_LT(r.final_residual, 1e-9 * r.initial_residual);
}

TEST(NewtonRoundOffFloor, SliverAtRestConvergesAtIterationZero) {
  // One tet of height 1e-9 over a unit triangle, one vertex fixed, no load: at rest, the
  // gradient is round-off only.
  Mesh mesh;
  mesh.rest_positions.resize(4, 3);
  mesh.rest_positions << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.3, 0.3, 1e-9;
  mesh.elements.resize(1, 4);
  mesh.elements << 0, 1, 2, 3;
  Model model(12);
  model.parameter_layout().add("youngs_modulus", 1);
  model.parameter_layout().add("poisson_ratio", 1);
  model.add(elastic_term<3>(mesh, MaterialKind::neo_hookean));
  model.set_elimination(Elimination::dirichlet({0, 1, 2}, rest_state(mesh)));
  Vector p(2);
  p << 1e6, 0.3;
  NewtonSolver newton(model);
  Vector y = model.elimination().restrict_state(rest_state(mesh)) + Vector::Constant(9, 1e-17);
  const NewtonResult r = newton.solve(p, y);
  EXPECT_TRUE(r.converged()) << r.report();
  EXPECT_EQ(r.iterations, 0) << r.report();
}

// Moduli 1e-3 next to the clamp and `stiff` beyond x = 1 on the linear bar.
NewtonResult solve_contrast(double stiff) {
  LinearBar bar;
  Vector p = bar.parameters(1.0);
  const int m = bar.mesh.num_elements();
  for (int e = 0; e < m; ++e) p[e] = bar.mesh.rest_positions(bar.mesh.elements(e, 0), 0) < 1.0 ? 1e-3 : stiff;
  NewtonSolver newton(bar.model);
  Vector y = bar.rest;
  return newton.solve(p, y);
}

TEST(NewtonRoundOffFloor, StiffContrastEndsQuicklyWithAClearStatus) {
  // A contrast of 1e9 is solvable in double precision: converged in a few iterations.
  const NewtonResult solvable = solve_contrast(1e6);
  EXPECT_TRUE(solvable.converged()) << solvable.report();
  EXPECT_LE(solvable.iterations, 3) << solvable.report();
  // 1e15 is not (the soft half carries the load, the stiff half's force round-off is about
  // half the load): Newton says so after the first step instead of running to its limit.
  const NewtonResult hopeless = solve_contrast(1e12);
  EXPECT_EQ(hopeless.status, NewtonStatus::ill_conditioned) << hopeless.report();
  EXPECT_FALSE(hopeless.converged());
  EXPECT_LE(hopeless.iterations, 3) << hopeless.report();
  EXPECT_GE(hopeless.condition_estimate, 1e14);
  EXPECT_NE(hopeless.message.find("condition number at least"), std::string::npos) << hopeless.message;
}

}  // namespace
}  // namespace tailor::newton_constant_test
