// The meshless solid through Newton and the adjoint: a Neo-Hookean bar clamped by the
// transformation method and bent by an end traction well into the nonlinear range; Newton
// converges on the exact Hessian, and the gradient and Hessian-vector products of a misfit of
// the MLS field at the tip, in the per-node E and nu, pass Taylor tests (rate >= 1.9).
#include <gtest/gtest.h>

#include <cstdio>

#include "adjoint/static_functional.hpp"
#include "adjoint/taylor_test.hpp"
#include "forward/fem/loads.hpp"
#include "forward/meshless/essential_conditions.hpp"
#include "forward/meshless/meshless_elastic_term.hpp"
#include "forward/solve/fixed_preconditioner_cg.hpp"
#include "meshless_fixtures.hpp"
#include "objectives/linear_observations.hpp"

namespace tailor::meshless_adjoint_test {
namespace {

using namespace tailor::meshless_testing;

constexpr double kLength = 3.0;

struct Bar {
  MeshlessSolid solid;
  std::unique_ptr<Model> model;
  Vector p;
};

Bar neo_hookean_bar() {
  Bar b;
  b.solid = make_solid(box_shape(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(kLength, 1, 1)), 0.5, 2, 0);
  const MeshlessSolid& s = b.solid;
  const int n = s.num_nodes();
  b.model = std::make_unique<Model>(3 * n);
  b.model->parameter_layout().add("youngs_modulus", n);
  b.model->parameter_layout().add("poisson_ratio", n);
  b.model->add(std::make_unique<MeshlessElasticTerm<3>>(s.quadrature, make_material<3>(MaterialKind::neo_hookean), 0, n));
  // End traction (0, 0, -30) on x = L at one point per 0.5 x 0.5 cell (E = 1000: the tip's
  // centre drops by 2.0, two thirds of the length, and moves back by 0.8).
  Eigen::MatrixXd points(4, 3), densities(4, 3);
  Eigen::VectorXd weights = Eigen::VectorXd::Constant(4, 0.25);
  for (int k = 0; k < 4; ++k) {
    points.row(k) << kLength, 0.25 + 0.5 * (k % 2), 0.25 + 0.5 * (k / 2);
    densities.row(k) << 0, 0, -30;
  }
  b.model->add(std::make_unique<ExternalForceTerm>(meshless_point_forces(*s.mls, points, weights, densities)));
  std::vector<int> clamped;
  for (int a = 0; a < n; ++a)
    if (s.sampling.nodes(a, 0) < 1e-9) clamped.push_back(a);
  Eigen::MatrixXd targets(static_cast<Eigen::Index>(clamped.size()), 3);
  for (std::size_t i = 0; i < clamped.size(); ++i) targets.row(static_cast<Eigen::Index>(i)) = s.sampling.nodes.row(clamped[i]);
  b.model->set_elimination(mls_transformation(*s.mls, clamped, targets).elimination);
  b.p = uniform_parameters(n, 1000.0, 0.3);
  for (int a = 0; a < n; ++a) b.p[a] *= 1.0 + 0.1 * s.sampling.nodes(a, 0) / kLength;  // graded modulus
  return b;
}

TEST(MeshlessAdjoint, NewtonConvergesOnANonlinearBend) {
  const Bar b = neo_hookean_bar();
  NewtonOptions options;
  options.relative_tolerance = 1e-10;
  NewtonSolver solver(*b.model, options);
  Vector y = b.model->elimination().restrict_state(b.solid.rest());
  const NewtonResult r = solver.solve(b.p, y);
  ASSERT_TRUE(r.converged()) << r.report();
  const Vector x = b.model->elimination().expand(y);
  const Eigen::Vector3d tip = b.solid.mls->interpolate(x, Eigen::Vector3d(kLength, 0.5, 0.5));
  std::printf("Neo-Hookean bar 3 x 1 x 1, h = 0.5: tip at (%.4f, %.4f, %.4f) after %d Newton iterations\n", tip[0],
              tip[1], tip[2], r.iterations);
  EXPECT_LT(tip[2], 0.5 - 1.0);       // a deflection of more than the thickness
  EXPECT_LT(tip[0], kLength - 0.5);   // and the end moves back: the response is nonlinear
  EXPECT_LE(r.iterations, 30);
}

TEST(MeshlessAdjoint, TaylorTestsOfAFieldMisfitInPerNodeParameters) {
  const Bar b = neo_hookean_bar();
  const MeshlessSolid& s = b.solid;
  // Observations: the MLS field (not a coefficient) at three points of the end face.
  Triplets t;
  const std::vector<Eigen::Vector3d> where = {{kLength, 0.5, 0.5}, {kLength, 0.1, 0.9}, {kLength, 0.8, 0.2}};
  for (std::size_t i = 0; i < where.size(); ++i) {
    const MlsValues v = s.mls->evaluate(where[i]);
    for (std::size_t k = 0; k < v.nodes.size(); ++k)
      for (int c = 0; c < 3; ++c)
        t.emplace_back(3 * static_cast<int>(i) + c, 3 * v.nodes[k] + c, v.values[static_cast<Eigen::Index>(k)]);
  }
  SparseMatrix B(9, 3 * s.num_nodes());
  B.setFromTriplets(t.begin(), t.end());
  Vector targets(9);
  for (std::size_t i = 0; i < where.size(); ++i) targets.segment<3>(3 * static_cast<Eigen::Index>(i)) = where[i] + Eigen::Vector3d(0, 0, -0.9);
  auto objective = std::make_shared<LinearObservations>(B, targets, Vector::Ones(9));
  StaticFunctional f(*b.model, identity_map(static_cast<int>(b.p.size())), objective,
                     b.model->elimination().restrict_state(s.rest()));
  const TaylorTestResult gradient = taylor_test(f, b.p);
  EXPECT_TRUE(gradient.passed()) << gradient.message << "\n" << gradient.table();
  EXPECT_GE(gradient.rate1, 1.9);
  const TaylorTestResult hessian = taylor_test_hessian(f, b.p);
  EXPECT_TRUE(hessian.passed()) << hessian.message << "\n" << hessian.table();
  std::printf("Taylor tests in the %d per-node parameters: gradient rate %.2f, Hessian-vector rate %.2f\n",
              static_cast<int>(b.p.size()), gradient.rate1, hessian.rate1);
}

// Newton's steps by CG preconditioned with a fixed factor (forward/solve/fixed_preconditioner_cg.hpp):
// the bar's own rest Hessian, factorized once. The bend is large (the tip drops by two thirds of
// the length), so the Hessian drifts far from the preconditioner and CG needs more iterations at
// the end than at the start; Newton still takes the direct solve's iterations to the same
// equilibrium, since each CG solve meets 1e-8. A preconditioner of the wrong size, or an
// indefinite one, is refused.
TEST(MeshlessAdjoint, FixedPreconditionerCgTakesTheDirectSolvesNewtonIterations) {
  const Bar b = neo_hookean_bar();
  const Vector y0 = b.model->elimination().restrict_state(b.solid.rest());
  NewtonOptions options;
  options.relative_tolerance = 1e-10;
  NewtonSolver direct(*b.model, options);
  Vector y_direct = y0;
  const NewtonResult r_direct = direct.solve(b.p, y_direct);
  ASSERT_TRUE(r_direct.converged()) << r_direct.report();

  NewtonSolver at_rest(*b.model);
  ASSERT_TRUE(at_rest.factorize_hessian(b.p, y0, HessianMode::exact).positive_definite);
  auto cg = std::make_shared<FixedPreconditionerCg>(at_rest.hessian());
  options.linear_solver = cg;
  NewtonSolver iterative(*b.model, options);
  Vector y_cg = y0;
  const NewtonResult r_cg = iterative.solve(b.p, y_cg);
  ASSERT_TRUE(r_cg.converged()) << r_cg.report();
  std::printf("fixed-preconditioner CG: %d Newton iterations (direct: %d), CG iterations per step:", r_cg.iterations,
              r_direct.iterations);
  for (const NewtonIteration& it : r_cg.history) std::printf(" %d", it.cg_iterations);
  std::printf("\n");
  EXPECT_EQ(r_cg.iterations, r_direct.iterations);
  EXPECT_LT((y_cg - y_direct).lpNorm<Eigen::Infinity>(), 1e-7 * y_direct.lpNorm<Eigen::Infinity>());
  // The first step is at the preconditioner's own state: one application solves it.
  EXPECT_EQ(r_cg.history.front().cg_iterations, 1);
  EXPECT_GT(r_cg.history.back().cg_iterations, 1);
  EXPECT_EQ(cg->info().solves, r_cg.iterations);

  std::string message;
  EXPECT_FALSE(cg->setup(SparseMatrix(3, 3), message));
  EXPECT_NE(message.find("rows"), std::string::npos);
  SparseMatrix indefinite = at_rest.hessian();
  indefinite.coeffRef(0, 0) = -1.0;
  EXPECT_THROW(FixedPreconditionerCg{indefinite}, std::runtime_error);
}

}  // namespace
}  // namespace tailor::meshless_adjoint_test
