// A homogeneous cell must return its own material's tensor whatever the cell shape and mesh:
// the affine field u = eps_bar X is the exact minimizer (zero fluctuation), so C^H = C to
// round-off (reference: the isotropic Hooke's law, e.g. Timoshenko & Goodier, Theory of
// Elasticity, ch. 1; plane stress and plane strain forms).
#include <gtest/gtest.h>

#include <random>

#include "forward/homogenization/cell_mesh.hpp"
#include "forward/homogenization/engineering_constants.hpp"
#include "forward/homogenization/linear_homogenization.hpp"

namespace tailor::homogeneous_cell_test {
namespace {

double relative_error(const Matrix& a, const Matrix& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

// Moves interior vertices randomly (the mesh stays periodic and valid): an unstructured mesh.
Mesh jiggle_interior(Mesh mesh, const Eigen::MatrixXd& lattice, const Eigen::VectorXd& origin, double amount,
                     unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amount, amount);
  const Eigen::MatrixXd inverse = lattice.inverse();
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::VectorXd f = inverse * (mesh.rest_positions.row(v).transpose() - origin);
    if ((f.array() < 1e-9).any() || (f.array() > 1.0 - 1e-9).any()) continue;
    Eigen::VectorXd df(f.size());
    for (int k = 0; k < f.size(); ++k) df[k] = u(rng);
    mesh.rest_positions.row(v) += (lattice * df).transpose();
  }
  return mesh;
}

TEST(HomogeneousCell, PlaneStrainAndPlaneStressOnSkewedJiggledCells) {
  const double E = 3.0, nu = 0.3;
  Eigen::Matrix2d A;
  A << 1.0, 0.6, 0.0, 0.8;
  for (const TriangleSplit split : {TriangleSplit::forward, TriangleSplit::crossed}) {
    for (const bool plane_stress : {false, true}) {
      const Mesh mesh = jiggle_interior(lattice_triangle_mesh(A, Eigen::Vector2d(0.2, -0.1), 6, 5, split), A,
                                        Eigen::Vector2d(0.2, -0.1), 0.02, 3);
      LinearCell cell(make_periodic_cell(mesh, A, Eigen::Vector2d(0.2, -0.1)),
                      plane_stress ? PlaneMode::plane_stress : PlaneMode::plane_strain);
      const int ne = mesh.num_elements();
      const LinearHomogenization h = cell.solve(Vector::Constant(ne, E), Vector::Constant(ne, nu));
      EXPECT_LT(relative_error(h.stiffness, isotropic_stiffness(2, E, nu, plane_stress)), 1e-12)
          << "plane_stress " << plane_stress << "\n"
          << h.stiffness;
      EXPECT_LT(h.symmetry_error, 1e-13);
      const Matrix S = compliance(h.stiffness);
      // Plane stress: E(d) = E, nu = nu; plane strain: E / (1 - nu^2), nu / (1 - nu).
      const double E_expected = plane_stress ? E : E / (1.0 - nu * nu);
      const double nu_expected = plane_stress ? nu : nu / (1.0 - nu);
      for (const double theta : {0.0, 0.4, 1.3}) {
        const Vector d = plane_direction(2, 0, 1, theta), n = plane_direction(2, 0, 1, theta + M_PI / 2);
        EXPECT_NEAR(directional_youngs_modulus(S, d), E_expected, 1e-12 * E);
        EXPECT_NEAR(poisson_ratio(S, d, n), nu_expected, 1e-12);
        EXPECT_NEAR(shear_modulus(S, d, n), E / (2.0 * (1.0 + nu)), 1e-12 * E);
      }
    }
  }
}

TEST(HomogeneousCell, SkewedTetCell) {
  const double E = 70.0, nu = 0.33;
  Eigen::Matrix3d A;
  A << 1.0, 0.4, 0.2, 0.0, 0.9, -0.3, 0.0, 0.0, 1.2;
  const Mesh mesh = jiggle_interior(lattice_tet_mesh(A, Eigen::Vector3d::Zero(), 3, 3, 3), A,
                                    Eigen::Vector3d::Zero(), 0.03, 5);
  LinearCell cell(make_periodic_cell(mesh, A, Eigen::Vector3d::Zero()));
  const int ne = mesh.num_elements();
  const LinearHomogenization h = cell.solve(Vector::Constant(ne, E), Vector::Constant(ne, nu));
  EXPECT_LT(relative_error(h.stiffness, isotropic_stiffness(3, E, nu)), 1e-12) << h.stiffness;
  const Matrix S = compliance(h.stiffness);
  const Vector d = Vector{{1.0, 2.0, -0.5}}.normalized();
  EXPECT_NEAR(directional_youngs_modulus(S, d), E, 1e-11 * E);
}

TEST(HomogeneousCell, RejectsBadMaterialInput) {
  const Mesh mesh = lattice_triangle_mesh(Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero(), 2, 2);
  LinearCell cell(make_box_periodic_cell(mesh));
  EXPECT_THROW(cell.solve(Vector::Constant(3, 1.0), Vector::Constant(3, 0.3)), std::invalid_argument);
  EXPECT_THROW(cell.solve(Vector::Constant(8, -1.0), Vector::Constant(8, 0.3)), std::invalid_argument);
  EXPECT_THROW(cell.solve(Vector::Constant(8, 1.0), Vector::Constant(8, 0.5)), std::invalid_argument);
  EXPECT_THROW(LinearCell(make_periodic_cell(
                              lattice_tet_mesh(Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), 1, 1, 1),
                              Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()),
                          PlaneMode::plane_stress),
               std::invalid_argument);
}

}  // namespace
}  // namespace tailor::homogeneous_cell_test
