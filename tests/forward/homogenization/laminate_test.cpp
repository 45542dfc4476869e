// Layered cells against the exact laminate formulas (Backus 1962, "Long-wave elastic
// anisotropy produced by horizontal layering", J. Geophys. Res. 67; Milton, The Theory of
// Composites, 2002, sec. 9.5): in a laminate with normal n the tangential strains and the
// normal tractions are the same in every layer, which gives C^H in closed form. The exact
// fluctuation is piecewise affine across layers, so P1 elements aligned with the layers
// reproduce it to round-off.
#include <gtest/gtest.h>

#include <Eigen/LU>

#include "forward/homogenization/cell_mesh.hpp"
#include "forward/homogenization/engineering_constants.hpp"
#include "forward/homogenization/linear_homogenization.hpp"

namespace tailor::laminate_test {
namespace {

// The laminate formula for layers normal to the last axis, phases with Voigt stiffnesses C[k]
// and volume fractions f[k]. Voigt components split into tangential t (strains continuous)
// and normal n (stresses continuous): 2D t = {11}, n = {22, 12}; 3D t = {11, 22, 12},
// n = {33, 23, 13}. With <.> the volume average:
//   C_nn* = <C_nn^-1>^-1,   C_nt* = C_nn* <C_nn^-1 C_nt>,
//   C_tt* = <C_tt - C_tn C_nn^-1 C_nt> + <C_tn C_nn^-1> C_nn* <C_nn^-1 C_nt>.
Matrix laminate_stiffness(const std::vector<Matrix>& C, const std::vector<double>& f) {
  const int m = static_cast<int>(C[0].rows());
  const std::vector<int> t = m == 3 ? std::vector<int>{0} : std::vector<int>{0, 1, 5};
  const std::vector<int> n = m == 3 ? std::vector<int>{1, 2} : std::vector<int>{2, 3, 4};
  const auto block = [](const Matrix& M, const std::vector<int>& r, const std::vector<int>& c) {
    Matrix B(r.size(), c.size());
    for (std::size_t i = 0; i < r.size(); ++i)
      for (std::size_t j = 0; j < c.size(); ++j) B(i, j) = M(r[i], c[j]);
    return B;
  };
  Matrix inv_nn = Matrix::Zero(n.size(), n.size()), inv_nt = Matrix::Zero(n.size(), t.size());
  Matrix tn_inv = Matrix::Zero(t.size(), n.size()), schur = Matrix::Zero(t.size(), t.size());
  for (std::size_t k = 0; k < C.size(); ++k) {
    const Matrix Cnn_inv = block(C[k], n, n).inverse();
    inv_nn += f[k] * Cnn_inv;
    inv_nt += f[k] * Cnn_inv * block(C[k], n, t);
    tn_inv += f[k] * block(C[k], t, n) * Cnn_inv;
    schur += f[k] * (block(C[k], t, t) - block(C[k], t, n) * Cnn_inv * block(C[k], n, t));
  }
  const Matrix Cnn = inv_nn.inverse();
  const Matrix Cnt = Cnn * inv_nt;
  const Matrix Ctt = schur + tn_inv * Cnn * inv_nt;
  Matrix out = Matrix::Zero(m, m);
  for (std::size_t i = 0; i < t.size(); ++i)
    for (std::size_t j = 0; j < t.size(); ++j) out(t[i], t[j]) = Ctt(i, j);
  for (std::size_t i = 0; i < n.size(); ++i) {
    for (std::size_t j = 0; j < n.size(); ++j) out(n[i], n[j]) = Cnn(i, j);
    for (std::size_t j = 0; j < t.size(); ++j) out(n[i], t[j]) = out(t[j], n[i]) = Cnt(i, j);
  }
  return out;
}

double relative_error(const Matrix& a, const Matrix& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

// Three layers along the last axis: [0, 0.25) phase 0, [0.25, 0.625) phase 1, [0.625, 1) phase 2
// (grid lines at 8 divisions fall on the interfaces).
int layer_of(double f) { return f < 0.25 ? 0 : (f < 0.625 ? 1 : 2); }
const std::vector<double> kFractions = {0.25, 0.375, 0.375};
const double kYoung[3] = {1.0, 20.0, 4.0};
const double kPoisson[3] = {0.2, 0.35, 0.45};

TEST(Laminate, TriangleCellsPlaneStrainAndPlaneStress) {
  for (const bool plane_stress : {false, true}) {
    const Mesh mesh = lattice_triangle_mesh(Eigen::Vector2d(0.5, 2.0).asDiagonal(), Eigen::Vector2d::Zero(),
                                            3, 8, TriangleSplit::crossed);
    LinearCell cell(make_box_periodic_cell(mesh),
                    plane_stress ? PlaneMode::plane_stress : PlaneMode::plane_strain);
    const int ne = mesh.num_elements();
    Vector E(ne), nu(ne);
    for (int e = 0; e < ne; ++e) {
      double y = 0.0;
      for (int a = 0; a < 3; ++a) y += mesh.rest_positions(mesh.elements(e, a), 1) / 3.0;
      const int phase = layer_of(y / 2.0);
      E[e] = kYoung[phase];
      nu[e] = kPoisson[phase];
    }
    std::vector<Matrix> phases;
    for (int k = 0; k < 3; ++k)
      phases.push_back(isotropic_stiffness(2, kYoung[k], kPoisson[k], plane_stress));
    const LinearHomogenization h = cell.solve(E, nu);
    EXPECT_LT(relative_error(h.stiffness, laminate_stiffness(phases, kFractions)), 1e-12)
        << h.stiffness << "\n\n"
        << laminate_stiffness(phases, kFractions);
    // The laminate differs from the Voigt average (the test can fail).
    Matrix voigt = Matrix::Zero(3, 3);
    for (int k = 0; k < 3; ++k) voigt += kFractions[k] * phases[k];
    EXPECT_GT(relative_error(h.stiffness, voigt), 0.1);
  }
}

TEST(Laminate, TetCell) {
  const Mesh mesh =
      lattice_tet_mesh(Eigen::Vector3d(1.0, 0.5, 1.0).asDiagonal(), Eigen::Vector3d::Zero(), 2, 2, 8);
  LinearCell cell(make_box_periodic_cell(mesh));
  const int ne = mesh.num_elements();
  Vector E(ne), nu(ne);
  for (int e = 0; e < ne; ++e) {
    double z = 0.0;
    for (int a = 0; a < 4; ++a) z += mesh.rest_positions(mesh.elements(e, a), 2) / 4.0;
    E[e] = kYoung[layer_of(z)];
    nu[e] = kPoisson[layer_of(z)];
  }
  std::vector<Matrix> phases;
  for (int k = 0; k < 3; ++k) phases.push_back(isotropic_stiffness(3, kYoung[k], kPoisson[k]));
  const LinearHomogenization h = cell.solve(E, nu);
  EXPECT_LT(relative_error(h.stiffness, laminate_stiffness(phases, kFractions)), 1e-12)
      << h.stiffness << "\n\n"
      << laminate_stiffness(phases, kFractions);
}

// LinearCell::state_tangent against central differences of the solved states, and
// state_tangent_transpose as its transpose, on a cell with random per-element moduli (plane
// stress exercises the modulus scale dE'/dE).
TEST(Laminate, StateTangentMatchesDifferencesAndItsTranspose) {
  for (const bool plane_stress : {false, true}) {
    const Mesh mesh = lattice_triangle_mesh(Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero(), 4, 4,
                                            TriangleSplit::crossed);
    LinearCell cell(make_box_periodic_cell(mesh), plane_stress ? PlaneMode::plane_stress : PlaneMode::plane_strain);
    const int ne = mesh.num_elements();
    std::srand(7);
    const Vector E = Vector::Constant(ne, 2.0) + Vector::Random(ne);
    const Vector nu = Vector::Constant(ne, 0.3);
    const Vector dE = Vector::Random(ne);
    const double h = 1e-5;
    const std::vector<Vector> plus = cell.solve(E + h * dE, nu).states;
    const std::vector<Vector> minus = cell.solve(E - h * dE, nu).states;
    cell.solve(E, nu);
    EXPECT_EQ(cell.solved_youngs_modulus(), E);
    for (int I = 0; I < 3; ++I) {
      const Vector tangent = cell.state_tangent(I, dE);
      const Vector difference = (plus[I] - minus[I]) / (2.0 * h);
      ASSERT_GT(difference.norm(), 1e-3);  // the moduli move the state: the check can fail
      EXPECT_LT((tangent - difference).norm(), 1e-7 * difference.norm()) << "load case " << I;
      const Vector w = Vector::Random(tangent.size());
      EXPECT_NEAR(w.dot(tangent), cell.state_tangent_transpose(I, w).dot(dE), 1e-12 * std::abs(w.dot(tangent)) + 1e-14);
    }
    EXPECT_THROW(cell.state_tangent(3, dE), std::out_of_range);
    EXPECT_THROW(cell.state_tangent(0, Vector::Zero(ne + 1)), std::invalid_argument);
  }
}

}  // namespace
}  // namespace tailor::laminate_test
