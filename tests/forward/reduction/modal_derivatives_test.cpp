// Modal derivatives, Krylov blocks and the mass-orthonormal basis.
#include "forward/reduction/modal_derivatives.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "forward/fem/loads.hpp"
#include "forward/reduction/mass_orthonormal_basis.hpp"
#include "forward/reduction/modal_analysis.hpp"
#include "forward/solve/newton.hpp"
#include "reduction_fixtures.hpp"

namespace tailor::modal_derivatives_test {
namespace {

using namespace tailor::testing;

ElasticBody small_cantilever(MaterialKind kind) {
  return elastic_body(Eigen::Vector2d(4, 1), Eigen::Vector2i(16, 4), kind, true, 1000.0, 0.3, 1.0);
}

Matrix lowest_modes(const ElasticBody& body, int count) {
  ModalAnalysisOptions options;
  options.count = count;
  return modal_analysis(*body.model, body.dim(), body.rest, body.p, body.mass, options).modes;
}

// For StVK the Hessian is quadratic in x, so central differences of Hessian-vector products
// are exact: two very different steps agree to round-off, and H(a) b = H(b) a (a third
// derivative of the energy is symmetric).
TEST(ModalDerivatives, DirectionalStiffnessIsExactForStvk) {
  const ElasticBody body = small_cantilever(MaterialKind::stvk);
  const Matrix modes = lowest_modes(body, 2);
  const Vector h1 =
      stiffness_directional_derivative(*body.model, body.rest, body.p, modes.col(0), modes.col(1), 1e-4);
  const Vector h2 =
      stiffness_directional_derivative(*body.model, body.rest, body.p, modes.col(0), modes.col(1), 0.3);
  const Vector h3 =
      stiffness_directional_derivative(*body.model, body.rest, body.p, modes.col(1), modes.col(0), 0.05);
  EXPECT_LT((h1 - h2).norm(), 1e-8 * h2.norm());
  EXPECT_LT((h3 - h2).norm(), 1e-10 * h2.norm());
}

// For other materials the central difference is second order in the step.
TEST(ModalDerivatives, DirectionalStiffnessConvergesAtSecondOrderForNeoHookean) {
  const ElasticBody body = small_cantilever(MaterialKind::neo_hookean);
  const Matrix modes = lowest_modes(body, 2);
  const auto h = [&](double step) {
    return stiffness_directional_derivative(*body.model, body.rest, body.p, modes.col(0), modes.col(1), step);
  };
  const Vector reference = h(1e-3);
  const double e1 = (h(0.2) - reference).norm(), e2 = (h(0.1) - reference).norm();
  std::printf("neo-Hookean FD error: step 0.2: %.3e, step 0.1: %.3e, ratio %.2f\n", e1, e2, e1 / e2);
  EXPECT_GT(e1 / e2, 3.5);
  EXPECT_LT(e1 / e2, 4.5);
}

// Independent check through Newton: the static equilibrium under the force eps K phi is
// u(eps) = eps phi + eps^2 / 2 Psi(phi, phi) + O(eps^3) (Barbic & James 2005, section 4), so
// (u(eps) + u(-eps)) / eps^2 -> Psi with an O(eps^2) error.
TEST(ModalDerivatives, AreTheSecondOrderStaticResponse) {
  ElasticBody body = small_cantilever(MaterialKind::stvk);
  const Matrix modes = lowest_modes(body, 2);
  const Matrix psi = modal_derivatives(*body.model, body.rest, body.p, modes);
  ASSERT_EQ(psi.cols(), 3);
  // Psi(a, a) for a = phi_0 + phi_1 is Psi_00 + 2 Psi_01 + Psi_11: checks the mixed column too.
  const Vector a = modes.col(0) + modes.col(1);
  const Vector psi_a = psi.col(modal_derivative_index(0, 0, 2)) +
                       2 * psi.col(modal_derivative_index(1, 0, 2)) +
                       psi.col(modal_derivative_index(1, 1, 2));
  const Vector k_a = body.model->hessian_times(body.rest, body.p, a);
  auto& load = body.model->add(std::make_unique<ExternalForceTerm>(Vector::Zero(k_a.size())));
  const auto response = [&](double eps) {
    load = ExternalForceTerm(eps * k_a);
    NewtonSolver newton(*body.model);
    newton.options().relative_tolerance = 1e-13;
    Vector y = body.model->elimination().restrict_state(body.rest);
    const NewtonResult result = newton.solve(body.p, y);
    EXPECT_TRUE(result.converged()) << result.message;
    return Vector(body.model->state(y, body.p) - body.rest);
  };
  double previous = 1e9;
  for (double eps : {0.02, 0.01}) {
    const double scale = eps / a.cwiseAbs().maxCoeff();  // largest displacement eps (length 4 beam)
    const Vector second = (response(scale) + response(-scale)) / (scale * scale);
    const double error = (second - psi_a).norm() / psi_a.norm();
    std::printf("largest displacement %.3f: relative error of the second-order response %.3e\n", eps, error);
    EXPECT_LT(error, 5e-3);
    EXPECT_LT(error, previous / 3.0);
    previous = error;
  }
}

TEST(ModalDerivatives, KrylovBlocksOfModesOnlyRescaleThem) {
  const ElasticBody body = small_cantilever(MaterialKind::stvk);
  ModalAnalysisOptions options;
  options.count = 3;
  const ModalAnalysis modes = modal_analysis(*body.model, 2, body.rest, body.p, body.mass, options);
  const Matrix blocks = krylov_blocks(*body.model, body.rest, body.p, body.mass, modes.modes, 2);
  ASSERT_EQ(blocks.cols(), 6);
  for (int c = 0; c < 6; ++c)
    EXPECT_NEAR(std::abs(blocks.col(c).dot(body.mass * modes.modes.col(c % 3))), 1.0, 1e-8);
  // So the basis built from modes + blocks keeps only the modes.
  Matrix all(modes.modes.rows(), 9);
  all << modes.modes, blocks;
  EXPECT_EQ(mass_orthonormal_basis(all, body.mass).cols(), 3);
}

TEST(MassOrthonormalBasis, RemovesDuplicatesAndKeepsNewDirections) {
  const ElasticBody body = small_cantilever(MaterialKind::stvk);
  const Matrix modes = lowest_modes(body, 2);
  const Matrix psi = modal_derivatives(*body.model, body.rest, body.p, modes);
  Matrix all(modes.rows(), 7);
  const Vector noise = Vector::Random(modes.rows()) * 1e-9;
  all << modes, psi, psi.col(0) + noise, 2.0 * modes.col(1);  // a near-duplicate and a duplicate
  std::vector<int> kept;
  const Matrix basis = mass_orthonormal_basis(all, body.mass, 1e-6, &kept);
  EXPECT_EQ(kept, (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_LT((basis.transpose() * (body.mass * basis) - Matrix::Identity(5, 5)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_THROW(mass_orthonormal_basis(all, body.mass, 0.0), std::invalid_argument);
  EXPECT_THROW(mass_orthonormal_basis(all.topRows(3), body.mass), std::invalid_argument);
}

TEST(ModalDerivatives, NeedAConstrainedBody) {
  const ElasticBody block =
      elastic_body(Eigen::Vector2d(2, 1), Eigen::Vector2i(4, 2), MaterialKind::stvk, false);
  const Matrix some = Matrix::Random(block.rest.size(), 2);
  EXPECT_THROW(modal_derivatives(*block.model, block.rest, block.p, some), std::runtime_error);
}

}  // namespace
}  // namespace tailor::modal_derivatives_test
