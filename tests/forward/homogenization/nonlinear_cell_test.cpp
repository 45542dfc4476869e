// Nonlinear homogenization under an imposed macro deformation gradient.
#include <gtest/gtest.h>

#include "forward/homogenization/cell_mesh.hpp"
#include "forward/homogenization/engineering_constants.hpp"
#include "forward/homogenization/linear_homogenization.hpp"
#include "forward/homogenization/nonlinear_homogenization.hpp"

namespace tailor::nonlinear_cell_test {
namespace {

Mesh square_cell(int n) {
  return lattice_triangle_mesh(Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero(), n, n,
                               TriangleSplit::crossed);
}

// Two phases: a stiff disc of radius 0.3 in a soft matrix.
void disc_phases(const Mesh& mesh, Vector& E, Vector& nu) {
  E.resize(mesh.num_elements());
  nu = Vector::Constant(mesh.num_elements(), 0.3);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (int a = 0; a < 3; ++a) c += mesh.rest_positions.row(mesh.elements(e, a)).transpose() / 3.0;
    E[e] = (c - Eigen::Vector2d(0.5, 0.5)).norm() < 0.3 ? 10.0 : 1.0;
  }
}

TEST(NonlinearCell, HomogeneousCellReturnsTheMaterialStress) {
  // Reference: the material's own P(F) (the affine deformation is the equilibrium).
  Eigen::Matrix2d A;
  A << 1.0, 0.4, 0.0, 0.9;
  const Mesh mesh = lattice_triangle_mesh(A, Eigen::Vector2d::Zero(), 5, 5);
  const int ne = mesh.num_elements();
  NonlinearCell cell(make_periodic_cell(mesh, A, Eigen::Vector2d::Zero()), MaterialKind::neo_hookean,
                     Vector::Constant(ne, 2.0), Vector::Constant(ne, 0.3));
  Eigen::Matrix2d F;
  F << 1.3, 0.2, -0.1, 0.8;
  const MacroResponse r = cell.solve(F);
  ASSERT_TRUE(r.newton.converged()) << r.newton.message;
  MaterialEvaluation<2> m;
  make_material<2>(MaterialKind::neo_hookean)
      ->evaluate(F, lame_from_young_poisson(2.0, 0.3), true, false, HessianMode::exact, m);
  EXPECT_LT((r.stress - m.stress).norm(), 1e-10 * m.stress.norm());
  EXPECT_NEAR(r.energy_density, m.energy_density, 1e-12 * m.energy_density);
}

TEST(NonlinearCell, SmallStrainLimitIsTheLinearTensor) {
  const Mesh mesh = square_cell(8);
  Vector E, nu;
  disc_phases(mesh, E, nu);
  LinearCell linear(make_box_periodic_cell(mesh));
  const Matrix C = linear.solve(E, nu).stiffness;
  NonlinearCell cell(make_box_periodic_cell(mesh), MaterialKind::stvk, E, nu);
  const double t = 1e-6;
  Matrix H(2, 2);
  H << 1.0, 0.3, 0.3, -0.5;  // symmetric macro strain direction
  const MacroResponse r = cell.solve(Matrix::Identity(2, 2) + t * H);
  ASSERT_TRUE(r.newton.converged());
  const Vector expected = C * Vector{{H(0, 0), H(1, 1), 2.0 * H(0, 1)}};
  const Vector observed = voigt_stress(r.stress) / t;
  EXPECT_LT((observed - expected).norm(), 1e-4 * expected.norm()) << observed.transpose() << "\n"
                                                                  << expected.transpose();
}

TEST(NonlinearCell, MacroStressIsTheEnergyDerivative) {
  // Hill-Mandel: P = dW/dF at equilibrium (central difference of the macro energy density).
  const Mesh mesh = square_cell(6);
  Vector E, nu;
  disc_phases(mesh, E, nu);
  NonlinearCell cell(make_box_periodic_cell(mesh), MaterialKind::neo_hookean, E, nu);
  Matrix F(2, 2), dF(2, 2);
  F << 1.25, 0.1, 0.05, 0.9;
  dF << 0.3, -0.7, 0.2, 0.5;
  const MacroResponse r = cell.solve(F);
  ASSERT_TRUE(r.newton.converged());
  const double h = 1e-5;
  const double Wp = cell.solve(F + h * dF).energy_density, Wm = cell.solve(F - h * dF).energy_density;
  const double directional = (r.stress.array() * dF.array()).sum();
  EXPECT_NEAR((Wp - Wm) / (2.0 * h), directional, 1e-6 * std::abs(directional));
}

TEST(NonlinearCell, StressStrainCurveToLargeStrain) {
  const Mesh mesh = square_cell(8);
  Vector E, nu;
  disc_phases(mesh, E, nu);
  NonlinearCell cell(make_box_periodic_cell(mesh), MaterialKind::neo_hookean, E, nu);
  Matrix H = Matrix::Zero(2, 2);
  H(0, 0) = 1.0;  // uniaxial macro strain along x up to 50 %
  const std::vector<MacroResponse> curve = macro_strain_path(cell, H, 0.5, 10);
  ASSERT_EQ(curve.size(), 11u);
  for (std::size_t k = 1; k < curve.size(); ++k) {
    EXPECT_TRUE(curve[k].newton.converged());
    EXPECT_GT(curve[k].stress(0, 0), curve[k - 1].stress(0, 0));  // monotone loading
  }
  EXPECT_LT(curve[0].stress.norm(), 1e-12);
  EXPECT_THROW(
      NonlinearCell(make_box_periodic_cell(mesh), MaterialKind::stvk, Vector::Ones(3), Vector::Ones(3)),
      std::invalid_argument);
}

}  // namespace
}  // namespace tailor::nonlinear_cell_test
