// Derivative checks of every material in 3D and plane strain: stress against central
// differences of the energy, tangent against central differences of the stress, Lame
// derivatives against differences in (lambda, mu) and, through lame_jacobian, in (E, nu).
#include <gtest/gtest.h>

#include "forward/fem/material.hpp"
#include "tests/forward/fem_materials/material_test_support.hpp"

namespace tailor::test::derivative_test {
namespace {

template <class T>
class MaterialDerivatives : public ::testing::Test {};
using Dims = ::testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(MaterialDerivatives, Dims);

// Steps relative to the size of F's entries: the first step is in the truncation-dominated
// regime, the smallest well above round-off.
template <int Dim>
double step_for(const Mat<Dim>& F) {
  return 5e-3 * std::max(1.0, F.cwiseAbs().maxCoeff());
}

template <int Dim>
double energy(const Material<Dim>& m, const Mat<Dim>& F, const LameParameters& lame) {
  MaterialEvaluation<Dim> e;
  m.evaluate(F, lame, false, false, HessianMode::exact, e);
  return e.energy_density;
}
template <int Dim>
Mat<Dim> stress(const Material<Dim>& m, const Mat<Dim>& F, const LameParameters& lame) {
  MaterialEvaluation<Dim> e;
  m.evaluate(F, lame, true, false, HessianMode::exact, e);
  return e.stress;
}

TYPED_TEST(MaterialDerivatives, StressMatchesEnergyDifferences) {
  constexpr int Dim = TypeParam::value;
  for (MaterialKind kind : all_kinds()) {
    const auto material = make_material<Dim>(kind);
    for (const LameCase& lc : lame_cases()) {
      const LameParameters lame = lc.lame();
      for (const auto& c : deformation_cases<Dim>()) {
        SCOPED_TRACE(to_string(kind) + " " + lc.name + " " + c.name);
        const auto fd = [&](double h) {
          Eigen::VectorXd d(Dim * Dim);
          for (int a = 0; a < Dim * Dim; ++a) {
            Mat<Dim> Fp = c.F, Fm = c.F;
            Fp.data()[a] += h;
            Fm.data()[a] -= h;
            d[a] = (energy<Dim>(*material, Fp, lame) - energy<Dim>(*material, Fm, lame)) / (2 * h);
          }
          return d;
        };
        const FdStudy s = fd_study(flat<Dim>(stress<Dim>(*material, c.F, lame)), fd, step_for<Dim>(c.F));
        EXPECT_TRUE(fd_converges(s, 1e-6 * (lame.lambda + lame.mu)));
      }
    }
  }
}

TYPED_TEST(MaterialDerivatives, TangentMatchesStressDifferences) {
  constexpr int Dim = TypeParam::value;
  for (MaterialKind kind : all_kinds()) {
    const auto material = make_material<Dim>(kind);
    for (const LameCase& lc : lame_cases()) {
      const LameParameters lame = lc.lame();
      for (const auto& c : deformation_cases<Dim>()) {
        SCOPED_TRACE(to_string(kind) + " " + lc.name + " " + c.name);
        MaterialEvaluation<Dim> e;
        material->evaluate(c.F, lame, true, true, HessianMode::exact, e);
        const auto fd = [&](double h) {
          Eigen::MatrixXd d(Dim * Dim, Dim * Dim);
          for (int b = 0; b < Dim * Dim; ++b) {
            Mat<Dim> Fp = c.F, Fm = c.F;
            Fp.data()[b] += h;
            Fm.data()[b] -= h;
            d.col(b) =
                flat<Dim>((stress<Dim>(*material, Fp, lame) - stress<Dim>(*material, Fm, lame)) / (2 * h));
          }
          return Eigen::VectorXd(Eigen::Map<Eigen::VectorXd>(d.data(), d.size()));
        };
        const Eigen::MatrixXd T = e.tangent;
        const FdStudy s =
            fd_study(Eigen::Map<const Eigen::VectorXd>(T.data(), T.size()), fd, step_for<Dim>(c.F));
        EXPECT_TRUE(fd_converges(s, 1e-6 * (lame.lambda + lame.mu)));
        // A Hessian is symmetric.
        EXPECT_LE((e.tangent - e.tangent.transpose()).norm(), 1e-12 * e.tangent.norm());
      }
    }
  }
}

// Psi and P are linear in (lambda, mu) for all four materials (for the stable Neo-Hookean
// after the reparametrisation), so these differences are exact up to round-off; the (E, nu)
// test below exercises the nonlinear chain with a genuine h^2 convergence.
TYPED_TEST(MaterialDerivatives, LameDerivativesMatchDifferences) {
  constexpr int Dim = TypeParam::value;
  for (MaterialKind kind : all_kinds()) {
    const auto material = make_material<Dim>(kind);
    for (const LameCase& lc : lame_cases()) {
      const LameParameters lame = lc.lame();
      for (const auto& c : deformation_cases<Dim>()) {
        SCOPED_TRACE(to_string(kind) + " " + lc.name + " " + c.name);
        MaterialLameDerivatives<Dim> d;
        material->lame_derivatives(c.F, lame, d);
        for (int which = 0; which < 2; ++which) {
          SCOPED_TRACE(which == 0 ? "d/dlambda" : "d/dmu");
          const double scale = which == 0 ? lame.lambda : lame.mu;
          const auto shifted = [&](double h) {
            LameParameters l = lame;
            (which == 0 ? l.lambda : l.mu) += h;
            return l;
          };
          const auto fd = [&](double h) {
            MaterialEvaluation<Dim> ep, em;
            material->evaluate(c.F, shifted(h), true, false, HessianMode::exact, ep);
            material->evaluate(c.F, shifted(-h), true, false, HessianMode::exact, em);
            Eigen::VectorXd v(1 + Dim * Dim);
            v[0] = (ep.energy_density - em.energy_density) / (2 * h);
            v.tail(Dim * Dim) = flat<Dim>((ep.stress - em.stress) / (2 * h));
            return v;
          };
          Eigen::VectorXd analytic(1 + Dim * Dim);
          analytic[0] = d.energy_density[which];
          analytic.tail(Dim * Dim) = d.stress.col(which);
          const FdStudy s = fd_study(analytic, fd, 1e-2 * scale);
          EXPECT_TRUE(fd_converges(s, 1e-8));
        }
      }
    }
  }
}

// Chain through lame_jacobian: d(Psi, P)/d(E, nu) = d(Psi, P)/d(lambda, mu) * J, against
// differences in E and nu of Psi(F; lame(E, nu)), which is nonlinear in nu.
TYPED_TEST(MaterialDerivatives, YoungPoissonChainMatchesDifferences) {
  constexpr int Dim = TypeParam::value;
  for (MaterialKind kind : all_kinds()) {
    const auto material = make_material<Dim>(kind);
    for (const LameCase& lc : lame_cases()) {
      for (const auto& c : deformation_cases<Dim>()) {
        SCOPED_TRACE(to_string(kind) + " " + lc.name + " " + c.name);
        MaterialLameDerivatives<Dim> d;
        material->lame_derivatives(c.F, lc.lame(), d);
        const Eigen::Matrix2d J = lame_jacobian(lc.youngs, lc.poisson);
        const Eigen::RowVector2d dpsi = d.energy_density.transpose() * J;
        const Eigen::Matrix<double, Dim * Dim, 2> dP = d.stress * J;
        for (int which = 0; which < 2; ++which) {
          SCOPED_TRACE(which == 0 ? "d/dE" : "d/dnu");
          const auto fd = [&](double h) {
            const double E = lc.youngs + (which == 0 ? h : 0.0), nu = lc.poisson + (which == 1 ? h : 0.0);
            const double Em = lc.youngs - (which == 0 ? h : 0.0), num = lc.poisson - (which == 1 ? h : 0.0);
            MaterialEvaluation<Dim> ep, em;
            material->evaluate(c.F, lame_from_young_poisson(E, nu), true, false, HessianMode::exact, ep);
            material->evaluate(c.F, lame_from_young_poisson(Em, num), true, false, HessianMode::exact, em);
            Eigen::VectorXd v(1 + Dim * Dim);
            v[0] = (ep.energy_density - em.energy_density) / (2 * h);
            v.tail(Dim * Dim) = flat<Dim>((ep.stress - em.stress) / (2 * h));
            return v;
          };
          Eigen::VectorXd analytic(1 + Dim * Dim);
          analytic[0] = dpsi[which];
          analytic.tail(Dim * Dim) = dP.col(which);
          // nu steps stay well inside (-1, 0.5): a fraction of the distance to 0.5.
          const double h0 = which == 0 ? 1e-2 * lc.youngs : 0.02 * (0.5 - lc.poisson);
          const FdStudy s = fd_study(analytic, fd, h0);
          EXPECT_TRUE(fd_converges(s, 1e-8));
        }
      }
    }
  }
}

}  // namespace
}  // namespace tailor::test::derivative_test
