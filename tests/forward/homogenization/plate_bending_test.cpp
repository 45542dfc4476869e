// Bending stiffness of plate-like cells against Kirchhoff plate theory (Timoshenko &
// Woinowsky-Krieger, Theory of Plates and Shells, ch. 1): a homogeneous plate of thickness t
// has D = E t^3 / (12 (1 - nu^2)) [[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]] (engineering
// twist), the exact 3D elasticity solution of pure bending. Linear tets converge to it as the
// mesh is refined (their parasitic shear in bending falls as h^2).
#include "forward/homogenization/plate_bending.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "forward/homogenization/cell_mesh.hpp"

namespace tailor::plate_bending_test {
namespace {

Matrix plate_theory(double E, double nu, double t) {
  const double D = E * t * t * t / (12.0 * (1.0 - nu * nu));
  Matrix out(3, 3);
  out << D, nu * D, 0.0, nu * D, D, 0.0, 0.0, 0.0, 0.5 * (1.0 - nu) * D;
  return out;
}

TEST(PlateBending, HomogeneousPlateConvergesToKirchhoffTheory) {
  const double E = 2.0, nu = 0.3, t = 0.5;
  const Eigen::Matrix3d A = Eigen::Vector3d(1.0, 1.0, t).asDiagonal();
  const Matrix reference = plate_theory(E, nu, t);
  std::vector<double> errors;
  std::vector<Matrix> computed;
  for (const int n : {4, 8, 16}) {
    const Mesh mesh = lattice_tet_mesh(A, Eigen::Vector3d::Zero(), n, n, std::max(2, n / 2));
    const PeriodicCell cell = make_periodic_cell(mesh, A, Eigen::Vector3d::Zero(), 1e-8, {true, true, false});
    const Matrix D = plate_bending_stiffness(cell, Vector::Constant(mesh.num_elements(), E),
                                             Vector::Constant(mesh.num_elements(), nu))
                         .stiffness;
    errors.push_back((D - reference).norm() / reference.norm());
    computed.push_back(D);
    std::printf("n = %2d: relative error of D %.3e\n", n, errors.back());
  }
  for (std::size_t k = 1; k < errors.size(); ++k) EXPECT_GT(std::log2(errors[k - 1] / errors[k]), 1.5);
  EXPECT_LT(errors.back(), 0.06);
  // The error is c h^2 to leading order: Richardson extrapolation of the two finest meshes.
  const Matrix extrapolated = (4.0 * computed[2] - computed[1]) / 3.0;
  const double extrapolated_error = (extrapolated - reference).norm() / reference.norm();
  std::printf("Richardson-extrapolated relative error %.3e\n", extrapolated_error);
  EXPECT_LT(extrapolated_error, 1e-8);
  EXPECT_NEAR(directional_bending_stiffness(reference, Vector{{1.0, 0.0}}), reference(0, 0), 1e-15);
}

TEST(PlateBending, RejectsFullyPeriodicCells) {
  const Mesh mesh = lattice_tet_mesh(Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), 2, 2, 2);
  const PeriodicCell cell = make_periodic_cell(mesh, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero());
  EXPECT_THROW(
      plate_bending_stiffness(cell, Vector::Ones(mesh.num_elements()), Vector::Zero(mesh.num_elements())),
      std::invalid_argument);
}

}  // namespace
}  // namespace tailor::plate_bending_test
