// The Krylov block recurrence of the static response to order k (krylov_recurrence.hpp).
#include "forward/reduction/krylov_recurrence.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "forward/fem/loads.hpp"
#include "forward/reduction/mass_orthonormal_basis.hpp"
#include "forward/reduction/modal_analysis.hpp"
#include "forward/reduction/modal_derivatives.hpp"
#include "forward/reduction/projected_reduced_model.hpp"
#include "forward/reduction/reduced_stvk.hpp"
#include "forward/solve/newton.hpp"
#include "reduction_fixtures.hpp"

namespace tailor::krylov_recurrence_test {
namespace {

using namespace tailor::testing;

ElasticBody cantilever(MaterialKind kind) {
  return elastic_body(Eigen::Vector2d(4, 1), Eigen::Vector2i(16, 4), kind, true, 1000.0, 0.3, 1.0);
}

Matrix lowest_modes(const ElasticBody& body, int count) {
  ModalAnalysisOptions options;
  options.count = count;
  return modal_analysis(*body.model, body.dim(), body.rest, body.p, body.mass, options).modes;
}

TEST(KrylovRecurrence, PartitionsAreCountedByBellNumbers) {
  EXPECT_EQ(nontrivial_partitions(2).size(), 1u);   // Bell(2) - 1
  EXPECT_EQ(nontrivial_partitions(3).size(), 4u);   // Bell(3) - 1
  EXPECT_EQ(nontrivial_partitions(4).size(), 14u);  // Bell(4) - 1
}

// Order 2 is the modal derivatives of Barbic & James 2005 (computed by modal_derivatives()).
TEST(KrylovRecurrence, OrderTwoIsTheModalDerivatives) {
  const ElasticBody body = cantilever(MaterialKind::stvk);
  const Matrix modes = lowest_modes(body, 3);
  KrylovRecurrenceOptions options;
  options.order = 3;
  const KrylovRecurrence k = krylov_recurrence(*body.model, body.rest, body.p, body.mass, modes, options);
  ASSERT_EQ(k.blocks.size(), 3u);
  EXPECT_EQ(k.blocks[1].cols(), 6);   // C(4, 2)
  EXPECT_EQ(k.blocks[2].cols(), 10);  // C(5, 3)
  const Matrix psi = modal_derivatives(*body.model, body.rest, body.p, modes);
  for (int c = 0; c < 6; ++c) {
    const auto& a = k.slots[1][c];
    const Vector expected = psi.col(modal_derivative_index(a[0], a[1], 3));
    EXPECT_LT((k.blocks[1].col(c) - expected).norm(), 1e-9 * expected.norm()) << c;
  }
}

// Galerkin static solve in span(V): minimise E(x_rest + V a) (loads included) by dense Newton.
Vector reduced_static_solve(const ElasticBody& body, const Matrix& basis) {
  const ProjectedReducedModel reduced(*body.model, body.p, body.rest, basis);
  Vector a = Vector::Zero(basis.cols());
  for (int it = 0; it < 50; ++it) {
    Vector g;
    Matrix h;
    reduced.evaluate(a, nullptr, &g, &h);
    const Vector step = h.ldlt().solve(-g);
    a += step;
    if (step.norm() <= 1e-14 * (1.0 + a.norm())) break;
  }
  return basis * a;
}

// The static response to the loads s K (phi_0 + phi_1) (largest linear displacement s on a
// beam of length 4): the reduced solve in span(P_1..P_k) differs from the full Newton solve by
// O(s^(k+1)), the order of the Taylor remainder. Reference: the full nonlinear FEM solve.
TEST(KrylovRecurrence, StaticResponseErrorFallsAsAmplitudeToTheOrderPlusOne) {
  ElasticBody body = cantilever(MaterialKind::stvk);
  const Matrix modes = lowest_modes(body, 2);
  Vector a = modes.col(0) + modes.col(1);
  a /= a.cwiseAbs().maxCoeff();
  const Vector k_a = body.model->hessian_times(body.rest, body.p, a);
  KrylovRecurrenceOptions options;
  options.order = 3;
  const KrylovRecurrence k = krylov_recurrence(*body.model, body.rest, body.p, body.mass, modes, options);
  auto& load = body.model->add(std::make_unique<ExternalForceTerm>(Vector::Zero(k_a.size())));
  for (int order = 1; order <= 3; ++order) {
    // Modes alone lock (their quartic stretching energy): order 1 is asymptotic only at smaller s.
    const std::vector<double> amplitudes =
        order == 1 ? std::vector<double>{4e-4, 2e-4, 1e-4} : std::vector<double>{0.02, 0.01, 0.005};
    Matrix vectors(body.rest.size(), 0);
    for (int j = 0; j < order; ++j) {
      vectors.conservativeResize(Eigen::NoChange, vectors.cols() + k.blocks[j].cols());
      vectors.rightCols(k.blocks[j].cols()) = k.blocks[j];
    }
    const Matrix basis = mass_orthonormal_basis(vectors, body.mass, 1e-10);
    std::vector<double> errors;
    for (double s : amplitudes) {
      load = ExternalForceTerm(s * k_a);
      NewtonSolver newton(*body.model);
      newton.options().relative_tolerance = 1e-14;
      Vector y = body.model->elimination().restrict_state(body.rest);
      ASSERT_TRUE(newton.solve(body.p, y).converged());
      const Vector full = body.model->state(y, body.p) - body.rest;
      errors.push_back((reduced_static_solve(body, basis) - full).norm() / full.norm());
    }
    for (std::size_t i = 1; i < errors.size(); ++i) {
      const double rate = std::log2(errors[i - 1] / errors[i]);
      // relative error ~ s^k, so the absolute error falls as s^(k+1)
      std::printf("order %d (%d columns): s = %.1e, relative error %.3e, rate of the relative error %.2f\n", order,
                  static_cast<int>(basis.cols()), amplitudes[i], errors[i], rate);
      EXPECT_NEAR(rate, order, 0.25) << "order " << order;
    }
  }
}

// Consistency with the exact StVK reduced polynomial (reduced_stvk.hpp, Barbic & James 2005):
// in the basis of the modes, its stiffness K_r(q) is quadratic, with dK_r/dq_c (e_b) =
// Phi^T F_2[phi_b, phi_c] and d2K_r/dq_c dq_d (e_b) = Phi^T F_3[phi_b, phi_c, phi_d]; central
// differences of a quadratic are exact, so both sides agree to round-off.
TEST(KrylovRecurrence, ForceDerivativesMatchTheStvkPolynomial) {
  const ElasticBody body = cantilever(MaterialKind::stvk);
  const Matrix modes = lowest_modes(body, 3);
  const ReducedStvk polynomial(*body.model, body.p, modes);
  const double h = 0.5, step = 4e-3;
  double worst2 = 0.0, worst3 = 0.0;
  const Eigen::Index r = modes.cols();
  for (int c = 0; c < r; ++c) {
    const Vector ec = Vector::Unit(r, c);
    const Matrix d2 = (polynomial.stiffness(h * ec) - polynomial.stiffness(-h * ec)) / (2 * h);
    for (int d = 0; d < r; ++d) {
      const Vector ed = Vector::Unit(r, d);
      const Matrix d3 = (polynomial.stiffness(h * (ec + ed)) - polynomial.stiffness(h * (ec - ed)) -
                         polynomial.stiffness(h * (ed - ec)) + polynomial.stiffness(-h * (ec + ed))) /
                        (4 * h * h);
      for (int b = 0; b < r; ++b) {
        const Vector f3 = modes.transpose() * force_derivative(*body.model, body.rest, body.p,
                                                               {modes.col(b), modes.col(c), modes.col(d)}, step);
        worst3 = std::max(worst3, (f3 - d3.col(b)).norm() / d3.norm());
      }
    }
    for (int b = 0; b < r; ++b) {
      const Vector f2 =
          modes.transpose() * force_derivative(*body.model, body.rest, body.p, {modes.col(b), modes.col(c)}, step);
      worst2 = std::max(worst2, (f2 - d2.col(b)).norm() / d2.norm());
    }
  }
  std::printf("StVK polynomial vs force derivatives: F_2 %.2e, F_3 %.2e\n", worst2, worst3);
  EXPECT_LT(worst2, 1e-9);
  EXPECT_LT(worst3, 1e-7);
  // The check sees an error: a neo-Hookean body's F_3 differs from the StVK polynomial's.
  const ElasticBody other = cantilever(MaterialKind::neo_hookean);
  const Vector f3 = modes.transpose() * force_derivative(*other.model, other.rest, other.p,
                                                         {modes.col(0), modes.col(0), modes.col(0)}, step);
  const Vector e0 = Vector::Unit(r, 0);
  const Matrix d3 = (polynomial.stiffness(2 * h * e0) - 2 * polynomial.stiffness(0 * e0) +
                     polynomial.stiffness(-2 * h * e0)) / (4 * h * h);
  EXPECT_GT((f3 - d3.col(0)).norm(), 1e-3 * d3.col(0).norm());
}

// Inertia blocks solve K b = c M p for each column p (c a positive scale).
TEST(KrylovRecurrence, InertiaBlocksAreStaticResponsesToInertialForces) {
  const ElasticBody body = cantilever(MaterialKind::stvk);
  const Matrix modes = lowest_modes(body, 2);
  KrylovRecurrenceOptions options;
  options.order = 2;
  options.inertia_blocks = true;
  const KrylovRecurrence k = krylov_recurrence(*body.model, body.rest, body.p, body.mass, modes, options);
  ASSERT_EQ(k.inertia.size(), 2u);
  EXPECT_EQ(k.all().cols(), 2 + 3 + 2 + 3);
  const Elimination& e = body.model->elimination();
  const Matrix& b = k.inertia[1];
  for (Eigen::Index c = 0; c < b.cols(); ++c) {
    const Vector kb = e.reduce(body.model->hessian_times(body.rest, body.p, b.col(c)));
    const Vector mp = e.reduce(body.mass * k.blocks[1].col(c));
    const double scale = kb.dot(mp) / mp.squaredNorm();
    EXPECT_GT(scale, 0.0);
    EXPECT_LT((kb - scale * mp).norm(), 1e-8 * kb.norm());
  }
  EXPECT_THROW(krylov_recurrence(*body.model, body.rest, body.p, body.mass, modes, {0, false, 0.0}),
               std::invalid_argument);
}

}  // namespace
}  // namespace tailor::krylov_recurrence_test
