// Projected (PSD) tangents: positive semidefinite, equal to the spectral clamp of the exact
// tangent, and equal to the exact tangent where that is already PSD.
#include <gtest/gtest.h>

#include "forward/core/symmetric_eigen.hpp"
#include "forward/fem/material.hpp"
#include "tests/forward/fem_materials/material_test_support.hpp"

namespace tailor::test::projection_test {
namespace {

template <class T>
class ProjectedTangent : public ::testing::Test {};
using Dims = ::testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(ProjectedTangent, Dims);

// The reference: Eigen's decomposition of the exact tangent with its negative eigenvalues clamped
// (the projection itself is tested in tests/forward/core/psd_projection_test.cpp).
Eigen::MatrixXd spectral_clamp(const Eigen::MatrixXd& A) {
  Eigen::VectorXd lambda;
  Eigen::MatrixXd V;
  symmetric_eigen(A, lambda, V);
  return V * lambda.cwiseMax(0.0).asDiagonal() * V.transpose();
}

template <int Dim>
std::vector<DeformationCase<Dim>> projection_cases() {
  auto cases = deformation_cases<Dim>();
  std::mt19937 rng(23);
  // Strong compression (StVK is indefinite there) and a rest state.
  cases.push_back(
      {"compressed", with_singular_values<Dim>(rng, Eigen::Matrix<double, Dim, 1>::Constant(0.3))});
  cases.push_back({"rest", Mat<Dim>::Identity()});
  // Random F of growing size, inverted ones included (repeated and degenerate singular values
  // are covered by "compressed" and "rest").
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double amplitude : {0.3, 1.0, 2.0})
    for (int r = 0; r < 8; ++r) {
      Mat<Dim> G;
      for (int j = 0; j < Dim; ++j)
        for (int i = 0; i < Dim; ++i) G(i, j) = u(rng);
      cases.push_back({"random_" + std::to_string(amplitude) + "_" + std::to_string(r),
                       Mat<Dim>::Identity() + amplitude * G});
    }
  return cases;
}

TYPED_TEST(ProjectedTangent, IsPsdAndTheSpectralClampOfTheExactTangent) {
  constexpr int Dim = TypeParam::value;
  int indefinite_cases = 0;
  // Physical settings plus an auxetic one (lambda < 0) and an unphysical negative shear modulus
  // (which sends the corotated material down its generic fallback).
  std::vector<std::pair<std::string, LameParameters>> settings;
  for (const LameCase& lc : lame_cases()) settings.emplace_back(lc.name, lc.lame());
  settings.emplace_back("nu=-0.5", lame_from_young_poisson(3.7, -0.5));
  settings.emplace_back("mu<0", LameParameters{1.0, -0.3});
  for (MaterialKind kind : all_kinds()) {
    const auto material = make_material<Dim>(kind);
    for (const auto& [setting, lame] : settings) {
      for (const auto& c : projection_cases<Dim>()) {
        SCOPED_TRACE(to_string(kind) + " " + setting + " " + c.name);
        MaterialEvaluation<Dim> exact, projected;
        material->evaluate(c.F, lame, true, true, HessianMode::exact, exact);
        material->evaluate(c.F, lame, true, true, HessianMode::projected, projected);
        // Energy and stress do not depend on the mode.
        EXPECT_EQ(exact.energy_density, projected.energy_density);
        EXPECT_EQ(exact.stress, projected.stress);
        const double scale = exact.tangent.norm();
        EXPECT_LE((projected.tangent - projected.tangent.transpose()).norm(), 1e-12 * scale);
        EXPECT_GE(min_eigenvalue(projected.tangent), -1e-10 * scale);
        EXPECT_LE((projected.tangent - spectral_clamp(exact.tangent)).norm(), 1e-9 * scale);
        const double exact_min = min_eigenvalue(exact.tangent);
        if (exact_min >= -1e-12 * scale) {
          EXPECT_LE((projected.tangent - exact.tangent).norm(), 1e-11 * scale);
        } else {
          ++indefinite_cases;
        }
      }
    }
  }
  // The cases must exercise the clamping, not only the fast path.
  EXPECT_GT(indefinite_cases, 10);
}

TYPED_TEST(ProjectedTangent, EqualsExactTangentAtRest) {
  constexpr int Dim = TypeParam::value;
  for (MaterialKind kind : all_kinds()) {
    const auto material = make_material<Dim>(kind);
    for (const LameCase& lc : lame_cases()) {
      SCOPED_TRACE(to_string(kind) + " " + lc.name);
      MaterialEvaluation<Dim> exact, projected;
      material->evaluate(Mat<Dim>::Identity(), lc.lame(), false, true, HessianMode::exact, exact);
      material->evaluate(Mat<Dim>::Identity(), lc.lame(), false, true, HessianMode::projected, projected);
      EXPECT_LE((projected.tangent - exact.tangent).norm(), 1e-12 * exact.tangent.norm());
    }
  }
}

}  // namespace
}  // namespace tailor::test::projection_test
