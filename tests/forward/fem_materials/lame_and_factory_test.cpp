// lame_from_young_poisson / lame_jacobian, and the material factory.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "forward/fem/material.hpp"
#include "tests/forward/fem_materials/material_test_support.hpp"

namespace tailor::test::lame_and_factory_test {
namespace {

TEST(Lame, KnownValues) {
  const LameParameters a = lame_from_young_poisson(1.0, 0.25);
  EXPECT_NEAR(a.lambda, 0.4, 1e-15);
  EXPECT_NEAR(a.mu, 0.4, 1e-15);
  const LameParameters b = lame_from_young_poisson(2.5, 0.0);
  EXPECT_EQ(b.lambda, 0.0);
  EXPECT_NEAR(b.mu, 1.25, 1e-15);
  const LameParameters c = lame_from_young_poisson(3.0, 0.3);  // lambda = 0.9/0.52, mu = 3/2.6
  EXPECT_NEAR(c.lambda, 0.9 / 0.52, 1e-14);
  EXPECT_NEAR(c.mu, 3.0 / 2.6, 1e-14);
  const LameParameters d = lame_from_young_poisson(1.0, -0.5);  // auxetic: lambda < 0, mu = 1
  EXPECT_NEAR(d.lambda, -0.5 / (0.5 * 2.0), 1e-15);
  EXPECT_NEAR(d.mu, 1.0, 1e-15);
}

TEST(Lame, JacobianMatchesDifferences) {
  for (const auto& [E_value, nu_value] : std::vector<std::pair<double, double>>{
           {1.0, 0.25}, {3.7, 0.3}, {2e5, 0.49}, {0.5, -0.7}, {3.7, 0.4999}}) {
    // Plain copies: C++17 lambdas cannot capture structured bindings (clang rejects it).
    const double E = E_value;
    const double nu = nu_value;
    SCOPED_TRACE("E=" + std::to_string(E) + " nu=" + std::to_string(nu));
    const Eigen::Matrix2d J = lame_jacobian(E, nu);
    for (int which = 0; which < 2; ++which) {
      const auto fd = [&](double h) {
        const LameParameters p = lame_from_young_poisson(E + (which == 0 ? h : 0), nu + (which == 1 ? h : 0));
        const LameParameters m = lame_from_young_poisson(E - (which == 0 ? h : 0), nu - (which == 1 ? h : 0));
        Eigen::VectorXd d(2);
        d << (p.lambda - m.lambda) / (2 * h), (p.mu - m.mu) / (2 * h);
        return d;
      };
      const double h0 = which == 0 ? 1e-2 * E : 0.02 * std::min(0.5 - nu, nu + 1.0);
      EXPECT_TRUE(fd_converges(fd_study(J.col(which), fd, h0), 1e-12 * E));
    }
  }
}

TEST(Lame, InvalidInputsThrowWithTheOffendingValue) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const auto& [E, nu] : std::vector<std::pair<double, double>>{{0.0, 0.3},
                                                                    {-2.0, 0.3},
                                                                    {nan, 0.3},
                                                                    {inf, 0.3},
                                                                    {1.0, 0.5},
                                                                    {1.0, 0.75},
                                                                    {1.0, -1.0},
                                                                    {1.0, -3.0},
                                                                    {1.0, nan}}) {
    SCOPED_TRACE("E=" + std::to_string(E) + " nu=" + std::to_string(nu));
    EXPECT_THROW(lame_from_young_poisson(E, nu), std::invalid_argument);
    EXPECT_THROW(lame_jacobian(E, nu), std::invalid_argument);
  }
  try {
    lame_from_young_poisson(1.0, 0.75);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("0.75"), std::string::npos) << e.what();
  }
  try {
    lame_from_young_poisson(-2.0, 0.3);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("-2"), std::string::npos) << e.what();
  }
}

TEST(MaterialFactory, NamesRoundTripAndUnknownNamesThrow) {
  for (MaterialKind kind : all_kinds()) {
    EXPECT_EQ(parse_material_kind(to_string(kind)), kind);
    EXPECT_EQ(make_material<2>(kind)->name(), to_string(kind));
    EXPECT_EQ(make_material<3>(kind)->name(), to_string(kind));
  }
  EXPECT_EQ(parse_material_kind("neo_hookean"), MaterialKind::neo_hookean);
  EXPECT_THROW(parse_material_kind("neohookean"), std::invalid_argument);
  EXPECT_THROW(parse_material_kind(""), std::invalid_argument);
  EXPECT_THROW(parse_material_kind("Linear"), std::invalid_argument);
}

// Only the requested outputs are written: energy always, stress/tangent on request.
TEST(MaterialFactory, EvaluateFillsOnlyWhatIsRequested) {
  const LameParameters lame = lame_from_young_poisson(1.0, 0.3);
  Mat<3> F;
  F << 1.1, 0.2, 0.0, -0.1, 0.9, 0.3, 0.05, 0.0, 1.2;
  for (MaterialKind kind : all_kinds()) {
    const auto m = make_material<3>(kind);
    MaterialEvaluation<3> e;
    e.stress.setConstant(42.0);
    e.tangent.setConstant(42.0);
    m->evaluate(F, lame, false, false, HessianMode::exact, e);
    EXPECT_GT(e.energy_density, 0.0) << to_string(kind);
    EXPECT_TRUE((e.stress.array() == 42.0).all()) << to_string(kind);
    EXPECT_TRUE((e.tangent.array() == 42.0).all()) << to_string(kind);
    MaterialEvaluation<3> full;
    m->evaluate(F, lame, true, true, HessianMode::exact, full);
    m->evaluate(F, lame, true, false, HessianMode::exact, e);
    EXPECT_EQ(e.stress, full.stress) << to_string(kind);
    EXPECT_TRUE((e.tangent.array() == 42.0).all()) << to_string(kind);
    EXPECT_EQ(e.energy_density, full.energy_density) << to_string(kind);
  }
}

}  // namespace
}  // namespace tailor::test::lame_and_factory_test
