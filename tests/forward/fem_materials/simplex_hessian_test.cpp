// The closed-form element Hessian of a linear simplex (Material::simplex_hessian) against the
// Hessian formed from the material's own exact tangent, V B^T T B with B = dvec(F)/dx. The
// tangent itself is checked against finite differences in derivative_test.cpp, so this pins the
// closed form to an independently verified quantity on every deformation case (inverted and
// nearly incompressible ones included).
#include <gtest/gtest.h>

#include <random>

#include "forward/fem/linear_simplices.hpp"
#include "tests/forward/fem_materials/material_test_support.hpp"

namespace tailor::test::simplex_hessian_test {
namespace {

template <int Dim>
void expect_closed_form_matches_tangent() {
  constexpr int kLocal = Dim * (Dim + 1);
  using Hessian = Eigen::Matrix<double, kLocal, kLocal>;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  int checked = 0;
  for (MaterialKind kind : all_kinds()) {
    const auto material = make_material<Dim>(kind);
    if (!material->has_simplex_hessian()) continue;
    for (const LameCase& lame : lame_cases())
      for (const DeformationCase<Dim>& deformation : deformation_cases<Dim>()) {
        // Shape gradients of a random non-degenerate simplex: rows sum to zero.
        typename Material<Dim>::NodeGradients G;
        G.template topRows<Dim>() =
            Mat<Dim>::Identity() + 0.4 * Mat<Dim>::NullaryExpr([&] { return coordinate(rng); });
        G.row(Dim) = -G.template topRows<Dim>().colwise().sum();
        const double V = 0.37;
        MaterialEvaluation<Dim> m;
        material->evaluate(deformation.F, lame.lame(), false, true, HessianMode::exact, m);
        const auto B = LinearSimplices<Dim>::deformation_jacobian(G);
        const Hessian reference = V * B.transpose() * m.tangent * B;
        Hessian closed;
        material->simplex_hessian(deformation.F, lame.lame(), G, V, closed.data());
        EXPECT_LE((closed - reference).norm(), 1e-12 * reference.norm())
            << material->name() << " " << lame.name << " " << deformation.name;
        ++checked;
      }
  }
  // Neo-Hookean has the closed form; a check over no material would pass vacuously.
  EXPECT_GT(checked, 0);
}

TEST(SimplexHessian, ClosedFormEqualsTheTangentsElementHessian3d) { expect_closed_form_matches_tangent<3>(); }
TEST(SimplexHessian, ClosedFormEqualsTheTangentsElementHessian2d) { expect_closed_form_matches_tangent<2>(); }

// The check can fail: a closed form whose determinant term has the wrong sign differs from the
// tangent's Hessian by far more than the tolerance on an inverted deformation.
TEST(SimplexHessian, AWrongDeterminantTermIsSeen) {
  const auto material = make_material<3>(MaterialKind::neo_hookean);
  Material<3>::NodeGradients G;
  G << 1, 0, 0, 0, 1, 0, 0, 0, 1, -1, -1, -1;
  Mat<3> F;
  F << 0.9, 0.2, 0.1, -0.1, 1.1, 0.3, 0.2, -0.2, -0.8;
  const LameParameters lame = lame_from_young_poisson(3.7, 0.3);
  Eigen::Matrix<double, 12, 12> closed;
  material->simplex_hessian(F, lame, G, 1.0, closed.data());
  // Recompute the skew determinant term and subtract it twice (its sign flipped).
  const double s = (lame.lambda + 5.0 / 6.0 * lame.mu) * (F.determinant() - 1.0) - lame.mu;
  Eigen::Matrix<double, 12, 12> wrong = closed;
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) {
      const Eigen::Vector3d w = s * (F * G.row(a).transpose().cross(G.row(b).transpose()));
      Mat<3> skew;
      skew << 0, w(2), -w(1), -w(2), 0, w(0), w(1), -w(0), 0;
      wrong.block<3, 3>(3 * a, 3 * b) -= 2.0 * skew;
    }
  MaterialEvaluation<3> m;
  material->evaluate(F, lame, false, true, HessianMode::exact, m);
  const auto B = LinearSimplices<3>::deformation_jacobian(G);
  const Eigen::Matrix<double, 12, 12> reference = B.transpose() * m.tangent * B;
  EXPECT_LE((closed - reference).norm(), 1e-12 * reference.norm());
  EXPECT_GT((wrong - reference).norm(), 1e-3 * reference.norm());
}

}  // namespace
}  // namespace tailor::test::simplex_hessian_test
