// Reduced StVK (exact polynomial precomputation) against the projected full model, and
// derivative checks of the reduced energy, force and stiffness.
#include "forward/reduction/reduced_stvk.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "adjoint/derivative_check.hpp"
#include "forward/reduction/mass_orthonormal_basis.hpp"
#include "forward/reduction/modal_analysis.hpp"
#include "forward/reduction/modal_derivatives.hpp"
#include "forward/reduction/projected_reduced_model.hpp"
#include "reduction_fixtures.hpp"

namespace tailor::reduced_stvk_test {
namespace {

using namespace tailor::testing;

// Modes plus their modal derivatives, mass-orthonormal.
Matrix modes_and_derivatives(const ElasticBody& body, int count) {
  ModalAnalysisOptions options;
  options.count = count;
  const Matrix modes = modal_analysis(*body.model, body.dim(), body.rest, body.p, body.mass, options).modes;
  const Matrix psi = modal_derivatives(*body.model, body.rest, body.p, modes);
  Matrix all(modes.rows(), modes.cols() + psi.cols());
  all << modes, psi;
  return mass_orthonormal_basis(all, body.mass);
}

// A q whose largest displacement is `size` (large deformation for a unit-size beam).
Vector deformation(const Matrix& basis, double size, unsigned seed) {
  std::srand(seed);
  const Vector q = Vector::Random(basis.cols());
  return q * size / (basis * q).cwiseAbs().maxCoeff();
}

void compare_with_projection(int dim) {
  const ElasticBody body =
      dim == 3 ? elastic_body(Eigen::Vector3d(4, 1, 1), Eigen::Vector3i(8, 2, 2), MaterialKind::stvk, true)
               : elastic_body(Eigen::Vector2d(4, 1), Eigen::Vector2i(16, 4), MaterialKind::stvk, true);
  const Matrix basis = modes_and_derivatives(body, 4);
  const ReducedStvk reduced(*body.model, body.p, basis);
  const ProjectedReducedModel projected(*body.model, body.p, body.rest, basis);
  std::printf("%dD: r = %d, precomputation %.4f s on %d threads\n", dim, reduced.size(),
              reduced.precomputation_seconds(), reduced.precomputation_threads());
  // Quadratic block = Phi^T K Phi.
  const Matrix stiffness_at_rest = projected.stiffness(Vector::Zero(basis.cols()));
  EXPECT_LT((reduced.stiffness(Vector::Zero(basis.cols())) - stiffness_at_rest).norm(),
            1e-11 * stiffness_at_rest.norm());
  for (double size : {0.01, 0.5, 2.0}) {
    const Vector q = deformation(basis, size, 7);
    double e_red = 0, e_full = 0;
    Vector f_red, f_full;
    Matrix k_red, k_full;
    reduced.evaluate(q, &e_red, &f_red, &k_red);
    projected.evaluate(q, &e_full, &f_full, &k_full);
    std::printf(
        "  largest displacement %.2f: energy %.6e vs %.6e, force error %.2e, stiffness error %.2e "
        "(relative)\n",
        size, e_red, e_full, (f_red - f_full).norm() / f_full.norm(),
        (k_red - k_full).norm() / k_full.norm());
    EXPECT_NEAR(e_red, e_full, 1e-11 * e_full);
    EXPECT_LT((f_red - f_full).norm(), 1e-11 * f_full.norm());
    EXPECT_LT((k_red - k_full).norm(), 1e-11 * k_full.norm());
  }
}

TEST(ReducedStvk, EqualsTheProjectedFullModel3d) { compare_with_projection(3); }
TEST(ReducedStvk, EqualsTheProjectedFullModel2d) { compare_with_projection(2); }

// Force = dW/dq and stiffness = d2W/dq2, by central differences along random directions.
void check_derivatives(const ReducedElasticModel& model, const Vector& q, bool expect_pass) {
  DerivativeCheckOptions options;
  options.initial_step = 1e-2;
  const Vector dq = Vector::Random(q.size()) * std::max(q.norm(), 1e-3);
  const DerivativeCheck gradient = check_directional_derivative(
      "force", [&](double t) { return Vector::Constant(1, model.energy(q + t * dq)); },
      Vector::Constant(1, model.force(q).dot(dq)), options);
  const DerivativeCheck hessian = check_directional_derivative(
      "stiffness", [&](double t) { return model.force(q + t * dq); }, Vector(model.stiffness(q) * dq),
      options);
  EXPECT_EQ(gradient.passed && hessian.passed, expect_pass) << gradient.message << " / " << hessian.message;
}

TEST(ReducedStvk, DerivativesPassTheCheck) {
  const ElasticBody body =
      elastic_body(Eigen::Vector3d(4, 1, 1), Eigen::Vector3i(4, 1, 1), MaterialKind::stvk, true);
  const Matrix basis = modes_and_derivatives(body, 3);
  const ReducedStvk reduced(*body.model, body.p, basis);
  for (double size : {0.05, 1.0}) check_derivatives(reduced, deformation(basis, size, 3), true);
}

TEST(ProjectedReducedModel, DerivativesPassTheCheckForNeoHookean) {
  const ElasticBody body =
      elastic_body(Eigen::Vector3d(4, 1, 1), Eigen::Vector3i(4, 1, 1), MaterialKind::neo_hookean, true);
  const Matrix basis = modes_and_derivatives(body, 3);
  const ProjectedReducedModel projected(*body.model, body.p, body.rest, basis);
  check_derivatives(projected, deformation(basis, 0.5, 3), true);
}

// The check can fail: a reduced model whose stiffness misses the cubic-term contribution.
class WrongStiffness final : public ReducedElasticModel {
 public:
  explicit WrongStiffness(const ReducedStvk& inner) : inner_(inner) {}
  int size() const override { return inner_.size(); }
  void evaluate(const Vector& q, double* energy, Vector* force, Matrix* stiffness) const override {
    inner_.evaluate(q, energy, force, stiffness);
    if (stiffness) *stiffness = inner_.stiffness(0.9 * q);
  }

 private:
  const ReducedStvk& inner_;
};

TEST(ReducedStvk, CorruptedStiffnessFailsTheCheck) {
  const ElasticBody body =
      elastic_body(Eigen::Vector3d(4, 1, 1), Eigen::Vector3i(4, 1, 1), MaterialKind::stvk, true);
  const Matrix basis = modes_and_derivatives(body, 3);
  const ReducedStvk reduced(*body.model, body.p, basis);
  check_derivatives(WrongStiffness(reduced), deformation(basis, 1.0, 3), false);
}

// The modal-derivative right-hand sides H(phi_i) phi_j (central differences of full-space
// Hessian-vector products) against the third derivatives of the precomputed polynomial.
TEST(ReducedStvk, ThirdDerivativesMatchTheDirectionalStiffness) {
  const ElasticBody body =
      elastic_body(Eigen::Vector2d(4, 1), Eigen::Vector2i(16, 4), MaterialKind::stvk, true);
  const Matrix basis = modes_and_derivatives(body, 3);
  const ReducedStvk reduced(*body.model, body.p, basis);
  const int r = reduced.size();
  for (int i = 0; i < 3; ++i) {
    // The reduced stiffness is quadratic in q: central differences are exact.
    const Vector e_i = Vector::Unit(r, i);
    const Matrix third = (reduced.stiffness(e_i) - reduced.stiffness(-e_i)) / 2.0;
    for (int j = 0; j < r; ++j) {
      const Vector full =
          basis.transpose() *
          stiffness_directional_derivative(*body.model, body.rest, body.p, basis.col(i), basis.col(j), 1e-2);
      EXPECT_LT((third.col(j) - full).norm(), 1e-9 * third.norm()) << i << ", " << j;
    }
  }
}

TEST(ReducedStvk, RejectsOtherMaterialsAndBadSizes) {
  const ElasticBody body =
      elastic_body(Eigen::Vector2d(2, 1), Eigen::Vector2i(2, 1), MaterialKind::neo_hookean, true);
  EXPECT_THROW(ReducedStvk(*body.model, body.p, Matrix::Identity(body.rest.size(), 2)),
               std::invalid_argument);
  const ElasticBody stvk =
      elastic_body(Eigen::Vector2d(2, 1), Eigen::Vector2i(2, 1), MaterialKind::stvk, true);
  EXPECT_THROW(ReducedStvk(*stvk.model, stvk.p, Matrix::Identity(3, 2)), std::invalid_argument);
  const ReducedStvk reduced(*stvk.model, stvk.p, Matrix::Identity(stvk.rest.size(), 2));
  EXPECT_THROW(reduced.energy(Vector::Zero(3)), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::reduced_stvk_test
