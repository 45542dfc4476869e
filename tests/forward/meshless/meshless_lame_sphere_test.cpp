// The thick-walled sphere under internal pressure against Lame's solution (linear elasticity;
// e.g. Timoshenko & Goodier, Theory of Elasticity, 3rd ed., section 136):
//   u_r(r) = p a^3 / (E (b^3 - a^3)) ((1 - 2 nu) r + (1 + nu) b^3 / (2 r^2)),
// a = 1, b = 2, on the octant x, y, z >= 0 with symmetry conditions (u_x = 0 on x = 0, ...)
// imposed per component by the transformation method, and the pressure on the inner surface by
// a Gauss rule in the spherical angles. The boundary is curved and not aligned with the cells:
// this exercises the clipped quadrature, the covering of cut cells and the per-component
// conditions. The table is printed; docs/meshless.md quotes it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "forward/fem/loads.hpp"
#include "forward/meshless/essential_conditions.hpp"
#include "forward/meshless/meshless_elastic_term.hpp"
#include "meshless_fixtures.hpp"

namespace tailor::meshless_lame_sphere_test {
namespace {

using namespace tailor::meshless_testing;

constexpr double kInner = 1.0, kOuter = 2.0, kPressure = 1.0, kModulus = 1000.0, kPoisson = 0.3;

double lame_radial_displacement(double r) {
  const double a3 = kInner * kInner * kInner, b3 = kOuter * kOuter * kOuter;
  return kPressure * a3 / (kModulus * (b3 - a3)) * ((1 - 2 * kPoisson) * r + (1 + kPoisson) * b3 / (2 * r * r));
}

// The pressure's consistent forces: traction p X / |X| on the inner octant surface, 8 x 8
// panels in (polar, azimuth) of 2 x 2 Gauss points each.
Vector pressure_forces(const MlsShapeFunctions& mls) {
  std::vector<double> gx, gw;
  gauss_legendre(2, gx, gw);
  const int panels = 8, count = panels * panels * 4;
  const double d = 0.5 * M_PI / panels;
  Eigen::MatrixXd points(count, 3), densities(count, 3);
  Eigen::VectorXd weights(count);
  int k = 0;
  for (int i = 0; i < panels; ++i)
    for (int j = 0; j < panels; ++j)
      for (std::size_t a = 0; a < 2; ++a)
        for (std::size_t b = 0; b < 2; ++b, ++k) {
          const double theta = d * (i + 0.5 * (1 + gx[a])), phi = d * (j + 0.5 * (1 + gx[b]));
          const Eigen::Vector3d n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
          points.row(k) = kInner * n.transpose();
          weights[k] = kInner * kInner * std::sin(theta) * 0.25 * d * d * gw[a] * gw[b];
          densities.row(k) = kPressure * n.transpose();
        }
  return meshless_point_forces(mls, points, weights, densities);
}

struct SphereResult {
  int nodes;
  double error;  // max over samples |u - u_Lame| / u_r(a)
};

SphereResult lame_sphere(double h) {
  MlsOptions mls;
  mls.support_factor = 2.0;
  const MeshlessSolid s = make_solid(shell_octant_shape(Eigen::Vector3d::Zero(), kInner, kOuter), h, 2, 2, mls);
  const int n = s.num_nodes();
  Model model(3 * n);
  model.parameter_layout().add("youngs_modulus", n);
  model.parameter_layout().add("poisson_ratio", n);
  model.add(std::make_unique<MeshlessElasticTerm<3>>(s.quadrature, make_material<3>(MaterialKind::linear), 0, n));
  model.add(std::make_unique<ExternalForceTerm>(pressure_forces(*s.mls)));
  std::array<MlsComponentConditions, 3> symmetry;
  for (int k = 0; k < 3; ++k) {
    std::vector<int>& nodes = symmetry[static_cast<std::size_t>(k)].nodes;
    for (int a = 0; a < n; ++a)
      if (std::abs(s.sampling.nodes(a, k)) < 1e-9) nodes.push_back(a);
    symmetry[static_cast<std::size_t>(k)].targets = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(nodes.size()));
  }
  const MlsEssentialConditions bc = mls_transformation(*s.mls, symmetry);
  model.set_elimination(bc.elimination);
  const Vector rest = s.rest();
  const Vector x = solve_equilibrium(model, uniform_parameters(n, kModulus, kPoisson), rest);
  // The symmetry conditions hold at their collocation points.
  for (int k = 0; k < 3; ++k)
    for (int a : symmetry[static_cast<std::size_t>(k)].nodes)
      EXPECT_NEAR(s.mls->interpolate(x, s.sampling.nodes.row(a).transpose())[k], 0.0, 1e-12);
  // Samples: 9 radii on 5 rays (the axes' neighbourhood excluded from nothing: rays inside).
  double error = 0.0;
  const std::vector<Eigen::Vector3d> rays = {{1, 1, 1}, {1, 0.2, 0.3}, {0.2, 1, 0.5}, {0.3, 0.4, 1}, {1, 1, 0.1}};
  for (const Eigen::Vector3d& ray : rays)
    for (int i = 0; i <= 8; ++i) {
      const double r = kInner + (kOuter - kInner) * (0.02 + 0.96 * i / 8.0);
      const Eigen::Vector3d e = ray.normalized(), X = r * e;
      const Eigen::Vector3d u = s.mls->interpolate(x, X) - X;
      error = std::max(error, (u - lame_radial_displacement(r) * e).norm());
    }
  return {n, error / lame_radial_displacement(kInner)};
}

TEST(MeshlessLameSphere, ConvergesToLamesSolution) {
  std::printf("thick sphere a = 1, b = 2, E = 1000, nu = 0.3, p = 1 (octant): u_r(a) = %.6e\n",
              lame_radial_displacement(kInner));
  std::printf("%10s %7s %22s %7s\n", "h", "nodes", "max |u - u_Lame|/u_r(a)", "rate");
  std::vector<double> spacings = {0.5, 1.0 / 3.0, 0.25}, errors;
  for (double h : spacings) {
    const SphereResult r = lame_sphere(h);
    const double rate = errors.empty() ? NAN : std::log(errors.back() / r.error) / std::log(spacings[errors.size() - 1] / h);
    std::printf("%10.4f %7d %22.3e %7.2f\n", h, r.nodes, r.error, rate);
    errors.push_back(r.error);
  }
  EXPECT_LT(errors[1], errors[0]);
  EXPECT_LT(errors[2], errors[1]);
  EXPECT_LT(errors[2], 0.05);
}

}  // namespace
}  // namespace tailor::meshless_lame_sphere_test
