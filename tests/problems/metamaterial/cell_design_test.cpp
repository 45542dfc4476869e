// Gradients of the cell-design functional (self-adjoint cell problems + SIMP + density
// filter) by Taylor tests, one per objective branch, plus the filter's properties.
#include "adjoint/scaled_gradient.hpp"
#include "problems/metamaterial/cell_design.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "adjoint/taylor_test.hpp"
#include "forward/homogenization/cell_mesh.hpp"

namespace tailor::cell_design_test {
namespace {

Vector random_design(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.2, 0.9);
  Vector z(n);
  for (auto& v : z) v = u(rng);
  return z;
}

std::shared_ptr<LinearCell> small_cell(PlaneMode mode) {
  Eigen::Matrix2d A;
  A << 1.0, 0.3, 0.0, 0.9;
  return std::make_shared<LinearCell>(
      make_periodic_cell(lattice_triangle_mesh(A, Eigen::Vector2d::Zero(), 8, 8), A, Eigen::Vector2d::Zero()),
      mode);
}

CellObjective entries_objective() {
  CellObjective o;
  o.entries = {{0, 0, 0.3, 1.0}, {0, 1, -0.05, 2.0}, {2, 2, 0.1, 1.0}, {1, 2, 0.0, 1.0}};
  return o;
}
CellObjective directional_objective(int dim) {
  CellObjective o;
  for (const double t : {0.0, 0.5, 1.2}) {
    Vector d = Vector::Zero(dim);
    d[0] = std::cos(t);
    d[1] = std::sin(t);
    if (dim == 3) d[2] = 0.3;
    o.directions.push_back(d);
    o.target_moduli.push_back(0.2 + t);
  }
  return o;
}
CellObjective poisson_objective() {
  CellObjective o;
  o.poisson_pairs = {{Vector{{1.0, 0.0}}, Vector{{0.0, 1.0}}}, {Vector{{0.0, 1.0}}, Vector{{1.0, 0.0}}}};
  o.poisson_target = -0.5;
  return o;
}

void expect_taylor_pass(ReducedFunctional& f, const Vector& z) {
  const TaylorTestResult t = taylor_test(f, z);
  std::printf("Taylor test: rate0 %.3f, rate1 %.3f (%s)\n", t.rate0, t.rate1, to_string(t.status).c_str());
  EXPECT_TRUE(t.passed()) << t.message << "\n" << t.table();
  EXPECT_GE(t.rate1, 1.9) << t.table();
  EXPECT_NEAR(t.rate0, 1.0, 0.15) << t.table();  // first order first: the remainder without the gradient
}

TEST(CellDesign, TaylorTestTargetEntries) {
  CellDesignFunctional f(small_cell(PlaneMode::plane_strain), SimpMaterial{}, 0.2, entries_objective());
  expect_taylor_pass(f, random_design(f.size(), 1));
}

TEST(CellDesign, TaylorTestDirectionalStiffnessPlaneStress) {
  CellDesignFunctional f(small_cell(PlaneMode::plane_stress), SimpMaterial{}, 0.2, directional_objective(2));
  expect_taylor_pass(f, random_design(f.size(), 2));
}

TEST(CellDesign, TaylorTestPoissonRatio) {
  CellDesignFunctional f(small_cell(PlaneMode::plane_strain), SimpMaterial{}, 0.15, poisson_objective());
  expect_taylor_pass(f, random_design(f.size(), 3));
}

TEST(CellDesign, TaylorTestPoissonRatioWithHeavisideProjection) {
  CellDesignFunctional f(small_cell(PlaneMode::plane_stress), SimpMaterial{}, 0.15, poisson_objective());
  f.set_projection(4.0);
  expect_taylor_pass(f, random_design(f.size(), 7));
  // The volume constraint's gradient through the projection (central difference).
  const Vector z = random_design(f.size(), 8), dz = random_design(f.size(), 9);
  Vector g;
  f.volume_fraction(z, &g);
  const double h = 1e-5;
  EXPECT_NEAR((f.volume_fraction(z + h * dz, nullptr) - f.volume_fraction(z - h * dz, nullptr)) / (2 * h),
              g.dot(dz), 1e-8);
}

TEST(CellDesign, TaylorTestDirectionalStiffness3D) {
  const Eigen::Matrix3d A = Eigen::Vector3d(1.0, 1.0, 0.8).asDiagonal();
  auto cell = std::make_shared<LinearCell>(
      make_periodic_cell(lattice_tet_mesh(A, Eigen::Vector3d::Zero(), 3, 3, 3), A, Eigen::Vector3d::Zero()));
  CellDesignFunctional f(cell, SimpMaterial{}, 0.35, directional_objective(3));
  expect_taylor_pass(f, random_design(f.size(), 4));
}

TEST(CellDesign, TaylorTestCatchesAPerturbedGradient) {
  CellDesignFunctional f(small_cell(PlaneMode::plane_strain), SimpMaterial{}, 0.15, poisson_objective());
  ScaledGradient bad(f, 1.01);  // a gradient off by 1% must fail the test
  const TaylorTestResult t = taylor_test(bad, random_design(f.size(), 3));
  EXPECT_FALSE(t.passed()) << t.table();
  EXPECT_LT(t.rate1, 1.2) << t.table();
}

TEST(CellDesign, FilterRowsAreAveragesAndVolumeGradientMatches) {
  auto cell = small_cell(PlaneMode::plane_strain);
  CellDesignFunctional f(cell, SimpMaterial{}, 0.2, entries_objective());
  const Vector ones = Vector::Ones(f.size());
  EXPECT_LT((f.densities(ones) - ones).cwiseAbs().maxCoeff(), 1e-14);
  // The filter smooths: a one-element spike spreads over its neighbourhood.
  Vector spike = Vector::Zero(f.size());
  spike[10] = 1.0;
  const Vector rho = f.densities(spike);
  EXPECT_LT(rho[10], 0.5);
  EXPECT_GT((rho.array() > 0.0).count(), 5);
  Vector g;
  const Vector z = random_design(f.size(), 5), dz = random_design(f.size(), 6);
  const double v = f.volume_fraction(z, &g);
  EXPECT_NEAR(f.volume_fraction(z + 1e-3 * dz, nullptr) - v, 1e-3 * g.dot(dz), 1e-12);  // linear
  EXPECT_THROW(CellDesignFunctional(cell, SimpMaterial{}, 2.0, entries_objective()), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::cell_design_test
