// Derivative checks of the principal-stretch spline material in 3D and plane strain: stress
// against central differences of the energy, tangent against central differences of the
// stress, on the hard cases of the SVD (all stretches equal, two equal, nearly equal by 1e-8 and
// 1e-12, inverted, 10x stretch, 0.1x compression); continuity of the tangent as two stretches
// merge; the projected tangent is the spectral clamp of the exact one.
#include <gtest/gtest.h>

#include "forward/fem/materials/spline_material.hpp"
#include "tests/forward/fem_materials/material_test_support.hpp"
#include "tests/forward/spline_material/spline_test_curves.hpp"

namespace tailor::test::spline_material_derivative_test {
namespace {

template <class T>
class SplineMaterialDerivatives : public ::testing::Test {};
using Dims = ::testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(SplineMaterialDerivatives, Dims);

template <int Dim>
std::vector<DeformationCase<Dim>> hard_cases() {
  std::mt19937 rng(77 + Dim);
  auto sv = [](double a, double b, double c) {
    Eigen::Matrix<double, Dim, 1> s;
    if constexpr (Dim == 3)
      s << a, b, c;
    else
      s << a, c;
    return s;
  };
  auto sv2 = [](double a, double b, double c) {  // in 2D keep the first two (equal pair in-plane)
    Eigen::Matrix<double, Dim, 1> s;
    if constexpr (Dim == 3)
      s << a, b, c;
    else
      s << a, b;
    return s;
  };
  std::vector<DeformationCase<Dim>> cases = deformation_cases<Dim>();
  cases.push_back({"rest", Mat<Dim>::Identity()});
  cases.push_back({"all_equal_1.2", with_singular_values<Dim>(rng, sv2(1.2, 1.2, 1.2))});
  cases.push_back({"two_equal", with_singular_values<Dim>(rng, sv2(1.3, 1.3, 0.8))});
  cases.push_back({"nearly_equal_1e-8", with_singular_values<Dim>(rng, sv2(1.2, 1.2 - 1e-8, 0.7))});
  cases.push_back({"nearly_equal_1e-12", with_singular_values<Dim>(rng, sv2(1.2, 1.2 - 1e-12, 0.7))});
  cases.push_back({"inverted", with_singular_values<Dim>(rng, sv(1.2, 0.9, -0.4))});
  cases.push_back({"inverted_two_equal", with_singular_values<Dim>(rng, sv2(1.1, 1.1, -0.5))});
  cases.push_back({"stretch_10x", with_singular_values<Dim>(rng, sv(10.0, 0.9, 0.8))});
  cases.push_back({"compression_0.1x", with_singular_values<Dim>(rng, sv(0.1, 0.1, 0.1))});
  return cases;
}

// fd_converges, but also accepting faster than second-order convergence (central differences
// of a function whose third derivative vanishes at the point converge at fourth order).
::testing::AssertionResult converges(const FdStudy& s, double min_reference, double rel_tol) {
  const auto r = fd_converges(s, min_reference, rel_tol);
  if (r) return r;
  const double order = std::log2(s.errors[0] / s.errors[1]);
  if (order > 2.3 && s.errors.back() / s.reference_norms.back() < rel_tol)
    return ::testing::AssertionSuccess();
  return r;
}

template <int Dim>
MaterialEvaluation<Dim> eval(const PrincipalStretchCurves& c, const Mat<Dim>& F,
                             HessianMode mode = HessianMode::exact) {
  MaterialEvaluation<Dim> e;
  evaluate_spline_material<Dim>(c, F, true, true, mode, e);
  return e;
}

TYPED_TEST(SplineMaterialDerivatives, StressAndTangentMatchDifferences) {
  constexpr int Dim = TypeParam::value;
  const PrincipalStretchCurves curves = generic_curves();
  for (const auto& c : hard_cases<Dim>()) {
    SCOPED_TRACE(c.name);
    const double h0 = 2e-3 * std::max(1.0, c.F.cwiseAbs().maxCoeff());
    const auto e = eval<Dim>(curves, c.F);
    const auto fd_stress = [&](double h) {
      Eigen::VectorXd d(Dim * Dim);
      for (int a = 0; a < Dim * Dim; ++a) {
        Mat<Dim> Fp = c.F, Fm = c.F;
        Fp.data()[a] += h;
        Fm.data()[a] -= h;
        d[a] = (eval<Dim>(curves, Fp).energy_density - eval<Dim>(curves, Fm).energy_density) / (2 * h);
      }
      return d;
    };
    EXPECT_TRUE(converges(fd_study(flat<Dim>(e.stress), fd_stress, h0), 1e-6, 1e-5));
    const auto fd_tangent = [&](double h) {
      Eigen::VectorXd d(Dim * Dim * Dim * Dim);
      for (int a = 0; a < Dim * Dim; ++a) {
        Mat<Dim> Fp = c.F, Fm = c.F;
        Fp.data()[a] += h;
        Fm.data()[a] -= h;
        d.segment(a * Dim * Dim, Dim * Dim) =
            flat<Dim>(Mat<Dim>((eval<Dim>(curves, Fp).stress - eval<Dim>(curves, Fm).stress) / (2 * h)));
      }
      return d;
    };
    const Eigen::Matrix<double, Dim * Dim, Dim* Dim> T = e.tangent;
    EXPECT_TRUE(converges(fd_study(Eigen::Map<const Eigen::VectorXd>(T.data(), T.size()), fd_tangent, h0),
                          1e-6, 1e-5));
    EXPECT_LE((T - T.transpose()).norm(), 1e-12 * T.norm());
  }
}

// As two stretches merge, the exact tangent converges to the one at coincidence: the flip
// eigenvalue is evaluated as a spline divided difference, without cancellation.
TYPED_TEST(SplineMaterialDerivatives, TangentIsContinuousAtCoincidentStretches) {
  constexpr int Dim = TypeParam::value;
  const PrincipalStretchCurves curves = generic_curves();
  std::mt19937 rng(5);
  const Mat<Dim> Q1 = random_rotation<Dim>(rng), Q2 = random_rotation<Dim>(rng);
  for (double base : {1.0, 1.3, 0.4}) {
    auto F_of = [&](double gap) {
      Eigen::Matrix<double, Dim, 1> s;
      if constexpr (Dim == 3)
        s << base + gap, base, 0.7;
      else
        s << base + gap, base;
      return Mat<Dim>(Q1 * s.asDiagonal() * Q2);
    };
    const auto T0 = eval<Dim>(curves, F_of(0.0)).tangent;
    for (double gap : {1e-4, 1e-8, 1e-12}) {
      const auto T = eval<Dim>(curves, F_of(gap)).tangent;
      // The tangent is smooth in F: differences O(gap) times its F-derivative (~ |T|).
      EXPECT_LE((T - T0).norm(), (20.0 * gap + 1e-12) * T0.norm()) << base << " " << gap;
    }
  }
}

TYPED_TEST(SplineMaterialDerivatives, ProjectedTangentIsTheSpectralClamp) {
  constexpr int Dim = TypeParam::value;
  const PrincipalStretchCurves curves = generic_curves();
  int indefinite = 0;
  for (const auto& c : hard_cases<Dim>()) {
    if (c.name.rfind("nearly_inverted", 0) == 0) continue;  // tangent ~1/(l_i + l_j): conditioning
    SCOPED_TRACE(c.name);
    const auto exact = eval<Dim>(curves, c.F);
    const auto projected = eval<Dim>(curves, c.F, HessianMode::projected);
    // The reference: Eigen's decomposition of the exact tangent, clamped.
    Eigen::VectorXd lambda;
    Eigen::MatrixXd V;
    symmetric_eigen(Eigen::MatrixXd(exact.tangent), lambda, V);
    const Eigen::MatrixXd clamp = V * lambda.cwiseMax(0.0).asDiagonal() * V.transpose();
    EXPECT_LE((projected.tangent - clamp).norm(), 1e-9 * exact.tangent.norm());
    if (lambda(0) < -1e-9 * exact.tangent.norm()) ++indefinite;
  }
  EXPECT_GT(indefinite, 0) << "no case exercised the clamping";
}

TYPED_TEST(SplineMaterialDerivatives, RotationInvariant) {
  constexpr int Dim = TypeParam::value;
  const PrincipalStretchCurves curves = generic_curves();
  std::mt19937 rng(9);
  for (const auto& c : hard_cases<Dim>()) {
    const Mat<Dim> R = random_rotation<Dim>(rng);
    const auto a = eval<Dim>(curves, c.F), b = eval<Dim>(curves, Mat<Dim>(R * c.F));
    EXPECT_NEAR(a.energy_density, b.energy_density, 1e-12 * (1 + std::abs(a.energy_density))) << c.name;
    EXPECT_LE((R * a.stress - b.stress).norm(), 1e-11 * (1 + a.stress.norm())) << c.name;
  }
}

}  // namespace
}  // namespace tailor::test::spline_material_derivative_test
