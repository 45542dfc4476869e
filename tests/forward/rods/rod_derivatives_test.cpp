// Derivative checks (adjoint/derivative_check.hpp) of the rod energies: stretching, bending and
// twisting, in the state and in every parameter block, on generic states and on the hard cases
// of the issue: a straight rod, nearly folded edges, a 1e-6-long edge between edges of length 1,
// a rod twisted 50 turns, rest curvature far larger than the current one, and reference frames
// stored at a state far from the evaluated one (the time-parallel transport's derivatives).
#include <gtest/gtest.h>

#include "adjoint/derivative_check.hpp"
#include "forward/core/symmetric_eigen.hpp"
#include "forward/rods/end_moment_term.hpp"
#include "rod_fixtures.hpp"

namespace tailor::rod_derivatives_test {
namespace {

using namespace tailor::testing;

// Perturbs every parameter by up to 20% so that no derivative is checked at a symmetric point.
Vector perturbed_parameters(const RodSetup& s, unsigned seed) {
  Vector p = s.p;
  const Vector u = uniform_noise(static_cast<int>(p.size()), seed);
  for (int i = 0; i < p.size(); ++i) p[i] = (p[i] == 0.0 ? 0.1 * u[i] : p[i] * (1.0 + 0.2 * u[i]));
  return p;
}

void expect_all_terms_pass(const RodSetup& s, const Vector& x, const Vector& p, const std::string& label,
                           DerivativeCheckOptions options = {}) {
  if (options.initial_step == DerivativeCheckOptions{}.initial_step) options.initial_step = 1e-4;
  for (const auto& term : s.model->terms()) {
    for (HessianMode mode : {HessianMode::exact}) {
      options.hessian_mode = mode;
      const EnergyTermCheck c = check_energy_term(*term, x, p, options);
      EXPECT_TRUE(c.passed()) << label << "\n" << c.table();
    }
  }
}

TEST(RodDerivatives, GenericHelixAllParameters) {
  RodMaterial m;
  m.youngs_modulus = 2.0;
  m.shear_modulus = 0.7;
  m.radius = 0.3;
  RodSetup s = make_rod(helix(7, 1.0, 0.2, 0.8), m);
  const Vector x = s.rest + 0.05 * uniform_noise(s.model->num_dofs(), 3);
  expect_all_terms_pass(s, x, perturbed_parameters(s, 4), "helix");
}

TEST(RodDerivatives, EllipseAndRectangleSections) {
  for (CrossSectionShape shape : {CrossSectionShape::ellipse, CrossSectionShape::rectangle}) {
    RodMaterial m;
    m.section = {shape, 0.4};
    RodSetup s = make_rod(helix(6, 1.0, 0.3, 0.6), m);
    const Vector x = s.rest + 0.1 * uniform_noise(s.model->num_dofs(), 5);
    expect_all_terms_pass(s, x, perturbed_parameters(s, 6), to_string(shape));
  }
}

// The stored frames belong to a state far from x (tangents turned by ~0.3 rad): the reference
// frame's transport contributes to every derivative (Bergou 2010's simplified gradient, exact
// only at the stored tangents, would fail here).
TEST(RodDerivatives, StaleReferenceFrames) {
  RodSetup s = make_rod(helix(6, 1.0, 0.2, 0.7));
  const Vector far = s.rest + 0.3 * uniform_noise(s.model->num_dofs(), 7);
  s.rod->update_reference_frames(far);
  const Vector x = s.rest + 0.3 * uniform_noise(s.model->num_dofs(), 8);
  expect_all_terms_pass(s, x, perturbed_parameters(s, 9), "stale frames");
}

// Straight rod: zero curvature binormal; the rest curvature is non-zero so that the gradient
// does not vanish identically.
TEST(RodDerivatives, StraightRod) {
  RodSetup s = make_rod(straight(6, 1.0));
  Vector x = s.rest;
  x.tail(s.rod->num_edges()) = 0.3 * uniform_noise(s.rod->num_edges(), 10);
  expect_all_terms_pass(s, x, perturbed_parameters(s, 11), "straight");
}

// Consecutive edges folded back to within 1e-3 rad of each other: |kb| = 2 tan(phi/2) ~ 2e3.
TEST(RodDerivatives, NearlyFoldedEdges) {
  Eigen::MatrixX3d pts(4, 3);
  const double gap = 1e-3;
  pts << 0, 0, 0, 1, 0, 0, 1 - std::cos(gap), std::sin(gap), 0.0, 1 - 2 * std::cos(gap), 2 * std::sin(gap),
      0.1;
  RodSetup s = make_rod(pts);
  Vector x = s.rest;
  x.tail(3) << 0.1, -0.2, 0.3;
  x.head(12) += 1e-4 * uniform_noise(12, 12);
  DerivativeCheckOptions o;
  o.state_scale = 1e-2;  // steps of 1e-6 and below, below the fold's gap of 1e-3
  expect_all_terms_pass(s, x, perturbed_parameters(s, 13), "nearly folded", o);
}

// An edge 1e-6 long between edges of length 1.
TEST(RodDerivatives, TinyEdgeBetweenUnitEdges) {
  Eigen::MatrixX3d pts(4, 3);
  // The tiny edge sits at the origin so that its coordinates carry full relative precision.
  pts << -1, 0, 0, 0, 0, 0, 1e-6, 0, 0, 1 + 1e-6, 0, 0;
  RodSetup s = make_rod(pts);
  Vector x = s.rest;
  x.head(12) += 1e-7 * uniform_noise(12, 14);
  x.tail(3) << 0.1, 0.2, -0.1;
  DerivativeCheckOptions o;
  o.state_scale = 1e-8;  // steps of 1e-10 and below, far below the tiny edge's length
  o.initial_step = 1e-2;
  expect_all_terms_pass(s, x, perturbed_parameters(s, 15), "tiny edge", o);
}

// Twist angles growing to 50 full turns along the rod, on a bent rod.
TEST(RodDerivatives, FiftyTurns) {
  RodSetup s = make_rod(helix(8, 1.0, 0.3, 0.5));
  Vector x = s.rest + 0.02 * uniform_noise(s.model->num_dofs(), 16);
  const int ne = s.rod->num_edges();
  for (int j = 0; j < ne; ++j) x[s.rod->twist_dof(j)] += 2.0 * M_PI * 50.0 * j / (ne - 1);
  DerivativeCheckOptions o;
  o.state_scale = 1.0;
  expect_all_terms_pass(s, x, perturbed_parameters(s, 17), "fifty turns", o);
}

// Rest curvature 100 times the current curvature.
TEST(RodDerivatives, RestCurvatureFarAboveCurrent) {
  RodSetup s = make_rod(helix(6, 10.0, 0.5, 0.1));
  Vector p = perturbed_parameters(s, 18);
  for (int i = 0; i < 2 * s.rod->num_interior(); ++i) p[s.blocks.rest_curvature + i] = 100.0 * (1 + i % 3);
  const Vector x = s.rest + 0.01 * uniform_noise(s.model->num_dofs(), 19);
  expect_all_terms_pass(s, x, p, "large rest curvature");
}

// The planar end moment E = -M phi(e): gradient and Hessian of the edge's angle.
TEST(RodDerivatives, EndMomentTerm) {
  RodSetup s = make_rod(helix(5, 1.0, 0.2, 0.5));
  const RodEndMomentTerm term(*s.rod, 3, Eigen::Vector3d(0.2, 0.1, 1.0), 1.7);
  const Vector x = s.rest + 0.1 * uniform_noise(s.model->num_dofs(), 21);
  DerivativeCheckOptions o;
  o.initial_step = 1e-4;
  const EnergyTermCheck c = check_energy_term(term, x, s.p, o);
  for (const auto& check : c.checks)
    if (check.quantity == "gradient" || check.quantity == "hessian") {
      EXPECT_TRUE(check.passed) << c.table();
    }
}

// HessianMode::projected: every term's assembled Hessian is positive semidefinite, on a state
// where the exact one is indefinite (compressed, strongly bent and twisted helix).
TEST(RodDerivatives, ProjectedHessianIsPositiveSemidefinite) {
  RodSetup s = make_rod(helix(8, 1.0, 0.2, 0.9));
  Vector x = 0.8 * s.rest + 0.2 * uniform_noise(s.model->num_dofs(), 22);
  bool some_exact_indefinite = false;
  for (const auto& term : s.model->terms()) {
    const Matrix exact = Matrix(term->hessian(x, s.p, HessianMode::exact));
    const Matrix projected = Matrix(term->hessian(x, s.p, HessianMode::projected));
    const auto lambda_exact = symmetric_eigenvalues(exact);
    const auto lambda = symmetric_eigenvalues(projected);
    EXPECT_GE(lambda.minCoeff(), -1e-10 * lambda.cwiseAbs().maxCoeff()) << term->name();
    some_exact_indefinite |= lambda_exact.minCoeff() < -1e-6 * lambda_exact.cwiseAbs().maxCoeff();
  }
  EXPECT_TRUE(some_exact_indefinite);
}

// A check must be able to fail: a wrong stiffness in the gradient is caught.
TEST(RodDerivatives, PerturbedDerivativeIsCaught) {
  RodSetup s = make_rod(helix(6, 1.0, 0.2, 0.7));
  const Vector x = s.rest + 0.05 * uniform_noise(s.model->num_dofs(), 20);
  const GradientTooStiff wrong(*s.bending);
  const EnergyTermCheck c = check_energy_term(wrong, x, s.p);
  EXPECT_FALSE(c.checks.front().passed) << c.table();
}

}  // namespace
}  // namespace tailor::rod_derivatives_test
