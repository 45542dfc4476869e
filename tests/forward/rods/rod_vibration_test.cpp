// First bending frequencies of a clamped-free rod against Euler-Bernoulli beam theory:
// omega_k = (beta_k L)^2 sqrt(EI / (rho A L^4)), beta_1 L = 1.87510407, beta_2 L = 4.69409113
// (roots of cos(bL) cosh(bL) = -1; e.g. Timoshenko, "Vibration Problems in Engineering").
// Stiffness: the exact Hessian of the rod energies at the straight rest state (transverse
// in-plane DOFs, which decouple from axial and twist DOFs there); mass: rho A h per Voronoi cell
// of the staggered grid (the vertex past the end carries none and is condensed statically).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>

#include "forward/core/symmetric_eigen.hpp"
#include "rod_fixtures.hpp"

namespace tailor::rod_vibration_test {
namespace {

using namespace tailor::testing;

// The two lowest in-plane bending frequencies for n cells (EI = 1, rho A = 1, L = 1).
Eigen::Vector2d cantilever_frequencies(int n) {
  const double h = 1.0 / n;
  Eigen::MatrixX3d pts = Eigen::MatrixX3d::Zero(n + 2, 3);
  for (int i = 0; i < n + 2; ++i) pts(i, 0) = (i - 0.5) * h;  // clamped edge centred on s = 0
  RodMaterial m;
  m.radius = 1e-2;
  m.youngs_modulus = 4.0 / (M_PI * std::pow(m.radius, 4));
  m.shear_modulus = m.youngs_modulus / 2.6;
  RodSetup s = make_rod(pts, m, Eigen::Vector3d::UnitZ());
  SparseMatrix H(s.model->num_dofs(), s.model->num_dofs());
  for (const auto& term : s.model->terms()) H += term->hessian(s.rest, s.p, HessianMode::exact);
  const Matrix K = Matrix(H);
  // Free transverse DOFs: y of vertices 2..n (massive) and n+1 (massless, condensed).
  const int nm = n - 1;
  Matrix Kmm(nm, nm), Km0(nm, 1);
  for (int a = 0; a < nm; ++a) {
    for (int b = 0; b < nm; ++b) Kmm(a, b) = K(s.rod->position_dof(a + 2, 1), s.rod->position_dof(b + 2, 1));
    Km0(a, 0) = K(s.rod->position_dof(a + 2, 1), s.rod->position_dof(n + 1, 1));
  }
  const double K00 = K(s.rod->position_dof(n + 1, 1), s.rod->position_dof(n + 1, 1));
  const Matrix condensed = (Kmm - Km0 * Km0.transpose() / K00) / h;  // M = h I
  const Eigen::VectorXd w2 = symmetric_eigenvalues(condensed);
  return {std::sqrt(w2[0]), std::sqrt(w2[1])};
}

TEST(RodVibration, CantileverBendingFrequenciesMatchEulerBernoulli) {
  const Eigen::Vector2d exact(std::pow(1.8751040687, 2), std::pow(4.6940911330, 2));
  Eigen::Vector2d previous;
  for (int n : {10, 20, 40}) {
    const Eigen::Vector2d w = cantilever_frequencies(n);
    const Eigen::Vector2d error = ((w - exact).array() / exact.array()).abs();
    std::printf("n = %d: omega_1 %.6f (error %.2e), omega_2 %.6f (error %.2e)\n", n, w[0], error[0], w[1],
                error[1]);
    if (n > 10) {
      EXPECT_GT(std::log2(previous[0] / error[0]), 1.8);
      EXPECT_GT(std::log2(previous[1] / error[1]), 1.8);
    }
    previous = error;
  }
  EXPECT_LT(previous[0], 2e-3);
  EXPECT_LT(previous[1], 5e-3);
}

}  // namespace
}  // namespace tailor::rod_vibration_test
