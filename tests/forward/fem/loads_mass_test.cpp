#include <gtest/gtest.h>

#include "../../support/fem_fixtures.hpp"
#include "forward/fem/loads.hpp"
#include "forward/fem/mass.hpp"

namespace tailor::loads_mass_test {
namespace {

using namespace tailor::testing;

// Sum of each force component over the vertices.
Vector resultant(const Vector& f, int dim) {
  Vector r = Vector::Zero(dim);
  for (Eigen::Index i = 0; i < f.size(); ++i) r[i % dim] += f[i];
  return r;
}

TEST(Loads, GravityResultantIsTotalWeight) {
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 0.5), 4, 2, 2);
  const Eigen::VectorXd density = Eigen::VectorXd::Constant(mesh.num_elements(), 7.0);
  const Vector f = gravity_forces(mesh, density, Eigen::Vector3d(0, 0, -9.81));
  const Vector r = resultant(f, 3);
  EXPECT_NEAR(r[2], -9.81 * 7.0 * 1.0, 1e-10);
  EXPECT_NEAR(r[0], 0.0, 1e-12);
  // The moment about the origin equals that of the weight at the centroid (1, 0.5, 0.25).
  double moment_y = 0.0;
  for (int v = 0; v < mesh.num_vertices(); ++v) moment_y += mesh.rest_positions(v, 0) * f[3 * v + 2];
  EXPECT_NEAR(moment_y, 1.0 * r[2], 1e-10);
}

TEST(Loads, TractionResultantIsTractionTimesArea) {
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 0.5), 4, 2, 2);
  const Eigen::MatrixXi end = boundary_facets_where(mesh, [](const Eigen::VectorXd& X) { return std::abs(X[0] - 2.0) < 1e-12; });
  const Vector f = traction_forces(mesh, end, Eigen::Vector3d(0.0, 3.0, -1.0));
  const Vector r = resultant(f, 3);
  EXPECT_NEAR(r[1], 3.0 * 0.5, 1e-12);
  EXPECT_NEAR(r[2], -1.0 * 0.5, 1e-12);
}

TEST(Loads, ExternalForceTermIsMinusWork) {
  const Vector f = Vector::LinSpaced(6, -1.0, 1.0);
  const ExternalForceTerm term(f);
  const Vector x = Vector::LinSpaced(6, 0.5, 2.0);
  EXPECT_DOUBLE_EQ(term.value(x, Vector()), -f.dot(x));
  Vector g = Vector::Zero(6);
  term.add_gradient(x, Vector(), g);
  EXPECT_EQ(g, -f);
  EXPECT_THROW(term.value(Vector::Zero(3), Vector()), std::invalid_argument);
}

TEST(Mass, ConsistentAndLumpedCarryTheTotalMass) {
  for (int dim : {2, 3}) {
    const Mesh mesh = small_mesh(dim);
    const Eigen::VectorXd density = Eigen::VectorXd::Constant(mesh.num_elements(), 2.5);
    const double total = 2.5 * element_volumes(mesh).sum();
    for (auto lumping : {MassLumping::consistent, MassLumping::lumped}) {
      const SparseMatrix M = mass_matrix(mesh, density, lumping);
      // A rigid translation along axis k has kinetic mass u^T M u = total mass.
      for (int k = 0; k < dim; ++k) {
        Vector u = Vector::Zero(M.rows());
        for (int v = 0; v < mesh.num_vertices(); ++v) u[dim * v + k] = 1.0;
        EXPECT_NEAR(u.dot(M * u), total, 1e-12 * total);
      }
    }
    // Consistent mass integrates linear fields exactly: u = X_0 along axis 0 gives
    // int rho X_0^2 dV, which for the box [0, 2] x ... is rho * A * 8 / 3.
    const SparseMatrix M = mass_matrix(mesh, density, MassLumping::consistent);
    Vector u = Vector::Zero(M.rows());
    for (int v = 0; v < mesh.num_vertices(); ++v) u[dim * v] = mesh.rest_positions(v, 0);
    const double cross_section = element_volumes(mesh).sum() / 2.0;
    EXPECT_NEAR(u.dot(M * u), 2.5 * cross_section * 8.0 / 3.0, 1e-12);
  }
}

}  // namespace
}  // namespace tailor::loads_mass_test
