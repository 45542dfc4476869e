// Presets against closed forms: linear corotated and StVK against the project's materials,
// the separable Neo-Hookean against its formula (Smith, de Goes, Kim 2018, without the
// log(I_C + 1) term), and every preset against linear elasticity at rest.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <iostream>

#include "forward/fem/materials/spline_material.hpp"
#include "tests/forward/fem_materials/material_test_support.hpp"

namespace tailor::test::presets_test {
namespace {

template <class T>
class SplinePresets : public ::testing::Test {};
using Dims = ::testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(SplinePresets, Dims);

template <int Dim>
MaterialEvaluation<Dim> eval(const Material<Dim>& m, const Mat<Dim>& F, const LameParameters& lame) {
  MaterialEvaluation<Dim> e;
  m.evaluate(F, lame, true, true, HessianMode::exact, e);
  return e;
}

// Largest relative deviation of energy, stress and tangent over the deformation cases.
template <int Dim>
double max_relative_deviation(const Material<Dim>& a, const Material<Dim>& b, const LameParameters& lame) {
  double worst = 0.0;
  const double scale = lame.lambda + 2.0 * lame.mu;
  for (const auto& c : deformation_cases<Dim>()) {
    const auto ea = eval<Dim>(a, c.F, lame), eb = eval<Dim>(b, c.F, lame);
    worst = std::max(worst, std::abs(ea.energy_density - eb.energy_density) /
                                (scale * (1 + std::abs(eb.energy_density) / scale)));
    worst = std::max(worst, (ea.stress - eb.stress).norm() / (scale + eb.stress.norm()));
    worst = std::max(worst, (ea.tangent - eb.tangent).norm() / (scale + eb.tangent.norm()));
  }
  return worst;
}

TYPED_TEST(SplinePresets, CorotatedIsExact) {
  constexpr int Dim = TypeParam::value;
  for (const LameCase& lc : lame_cases()) {
    const SplineMaterial<Dim> spline(principal_stretch_preset(SplinePreset::corotated, lc.lame()));
    EXPECT_LT(max_relative_deviation<Dim>(spline, *make_material<Dim>(MaterialKind::corotated), lc.lame()),
              1e-11)
        << lc.name;
  }
}

// f is quartic for StVK, so its cubic spline is not exact: the curvature (hence the tangent) is
// off by O(h^2), h the knot spacing. Measured with the default grid (h = 0.1): ~1.7e-3 relative
// (worst of energy, stress, tangent over the cases); a 4x finer grid must cut it ~16x.
TYPED_TEST(SplinePresets, StvkAgreesToTheStatedToleranceAndConvergesAtSecondOrder) {
  constexpr int Dim = TypeParam::value;
  PrincipalStretchGrids fine;
  fine.uniaxial.intervals *= 4;
  for (const LameCase& lc : lame_cases()) {
    const auto stvk = make_material<Dim>(MaterialKind::stvk);
    const SplineMaterial<Dim> coarse(principal_stretch_preset(SplinePreset::stvk, lc.lame()));
    const SplineMaterial<Dim> refined(principal_stretch_preset(SplinePreset::stvk, lc.lame(), fine));
    const double deviation = max_relative_deviation<Dim>(coarse, *stvk, lc.lame());
    const double fine_deviation = max_relative_deviation<Dim>(refined, *stvk, lc.lame());
    std::cout << "stvk preset deviation (" << Dim << "D, " << lc.name << "): h = 0.1: " << deviation
              << ", h = 0.025: " << fine_deviation << "\n";
    EXPECT_LT(deviation, 3e-3) << lc.name;
    EXPECT_GT(deviation, 1e-13) << "a quartic cannot be exact";
    EXPECT_GT(deviation / fine_deviation, 12.0) << lc.name;
  }
}

TYPED_TEST(SplinePresets, NeoHookeanMatchesItsClosedForm) {
  constexpr int Dim = TypeParam::value;
  for (const LameCase& lc : lame_cases()) {
    const LameParameters lame = lc.lame();
    const SplineMaterial<Dim> spline(principal_stretch_preset(SplinePreset::neo_hookean, lame));
    const double ls = lame.lambda + lame.mu, alpha = 1.0 + lame.mu / ls;
    for (const auto& c : deformation_cases<Dim>()) {
      // Plane strain: I_C = |F|^2 + 1, J = det F (2x2).
      const double Ic = c.F.squaredNorm() + (Dim == 2 ? 1.0 : 0.0), J = c.F.determinant();
      const double psi =
          0.5 * lame.mu * (Ic - 3.0) + 0.5 * ls * ((J - alpha) * (J - alpha) - (1 - alpha) * (1 - alpha));
      Mat<Dim> cof = J * c.F.inverse().transpose();
      const Mat<Dim> P = lame.mu * c.F + ls * (J - alpha) * cof;
      const auto e = eval<Dim>(spline, c.F, lame);
      const double scale = lame.lambda + 2 * lame.mu;
      EXPECT_NEAR(e.energy_density, psi, 1e-11 * scale * (1 + std::abs(psi) / scale))
          << lc.name << " " << c.name;
      EXPECT_LT((e.stress - P).norm(), 1e-11 * (scale + P.norm())) << lc.name << " " << c.name;
    }
  }
}

// Every preset is stress free at rest and has the tangent of linear elasticity there, as the
// project's stable Neo-Hookean does (reference: mu (dF + dF^T) + lambda tr(dF) I).
TYPED_TEST(SplinePresets, LinearElasticAtRest) {
  constexpr int Dim = TypeParam::value;
  const LameParameters lame = lame_from_young_poisson(3.7, 0.3);
  const auto linear = make_material<Dim>(MaterialKind::linear);
  const auto reference = eval<Dim>(*linear, Mat<Dim>::Identity(), lame);
  for (SplinePreset preset : {SplinePreset::corotated, SplinePreset::stvk, SplinePreset::neo_hookean}) {
    const SplineMaterial<Dim> spline(principal_stretch_preset(preset, lame));
    const auto e = eval<Dim>(spline, Mat<Dim>::Identity(), lame);
    // Exact presets to round-off; StVK's quartic f to its spline error (above).
    const double tolerance = preset == SplinePreset::stvk ? 3e-3 : 1e-12;
    const double scale = lame.lambda + 2 * lame.mu;
    EXPECT_NEAR(e.energy_density, 0.0, tolerance * scale);
    EXPECT_LT(e.stress.norm(), tolerance * scale);
    EXPECT_LT((e.tangent - reference.tangent).norm(), tolerance * reference.tangent.norm());
  }
  const auto nh = eval<Dim>(*make_material<Dim>(MaterialKind::neo_hookean), Mat<Dim>::Identity(), lame);
  EXPECT_LT((nh.tangent - reference.tangent).norm(), 1e-12 * reference.tangent.norm());
}

TEST(SplinePresets, ParsesNames) {
  EXPECT_EQ(parse_spline_preset("stvk"), SplinePreset::stvk);
  EXPECT_THROW(parse_spline_preset("mooney"), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::test::presets_test
