// Two-phase cells: bounds, symmetry and convergence under refinement.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "forward/core/symmetric_eigen.hpp"
#include "forward/homogenization/cell_mesh.hpp"
#include "forward/homogenization/engineering_constants.hpp"
#include "forward/homogenization/linear_homogenization.hpp"

namespace tailor::two_phase_cell_test {
namespace {

using PhaseOf = std::function<bool(const Eigen::Vector2d& centroid)>;  // true: phase 1

LinearHomogenization homogenize_two_phase(const Mesh& mesh, const Eigen::Matrix2d& A, const PhaseOf& phase_of,
                                          double E0, double nu0, double E1, double nu1,
                                          double* fraction = nullptr) {
  LinearCell cell(make_periodic_cell(mesh, A, Eigen::Vector2d::Zero()));
  const int ne = mesh.num_elements();
  Vector E(ne), nu(ne);
  const Eigen::VectorXd volumes = element_volumes(mesh);
  double f1 = 0.0;
  for (int e = 0; e < ne; ++e) {
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (int a = 0; a < 3; ++a) c += mesh.rest_positions.row(mesh.elements(e, a)).transpose() / 3.0;
    const bool one = phase_of(c);
    E[e] = one ? E1 : E0;
    nu[e] = one ? nu1 : nu0;
    f1 += one ? volumes[e] : 0.0;
  }
  if (fraction) *fraction = f1 / volumes.sum();
  return cell.solve(E, nu);
}

// Distance from x to the nearest lattice translate of `centre`.
double periodic_distance(const Eigen::Vector2d& x, const Eigen::Vector2d& centre, const Eigen::Matrix2d& A) {
  double best = 1e300;
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j) best = std::min(best, (x - centre - A * Eigen::Vector2d(i, j)).norm());
  return best;
}

// Hashin-Shtrikman bounds in 2D (plane strain: transverse bulk modulus k = lambda + mu and
// shear modulus mu of fibre composites; Hashin 1965, J. Mech. Phys. Solids 13; Torquato,
// Random Heterogeneous Materials, 2002, eq. 21.x with d = 2), for well-ordered phases
// (k1 >= k0, mu1 >= mu0); `stiff` selects the upper bound.
struct Moduli {
  double k, mu;
};
Moduli hashin_shtrikman(Moduli a, Moduli b, double fb) {  // reference phase a
  const double fa = 1.0 - fb;
  const double k = a.k + fb / (1.0 / (b.k - a.k) + fa / (a.k + a.mu));
  const double mu = a.mu + fb / (1.0 / (b.mu - a.mu) + fa * (a.k + 2.0 * a.mu) / (2.0 * a.mu * (a.k + a.mu)));
  return {k, mu};
}
Moduli plane_strain_moduli(double E, double nu) {
  const double mu = E / (2.0 * (1.0 + nu));
  return {E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)) + mu, mu};
}

TEST(TwoPhaseCell, RandomCellsStayWithinVoigtReussAndHashinShtrikmanBounds) {
  const double E0 = 1.0, nu0 = 0.3, E1 = 10.0, nu1 = 0.25;
  const Moduli soft = plane_strain_moduli(E0, nu0), stiff = plane_strain_moduli(E1, nu1);
  ASSERT_GE(stiff.k, soft.k);
  ASSERT_GE(stiff.mu, soft.mu);
  const Eigen::Matrix2d A = Eigen::Matrix2d::Identity();
  const Mesh mesh = lattice_triangle_mesh(A, Eigen::Vector2d::Zero(), 24, 24, TriangleSplit::crossed);
  for (const unsigned seed : {1u, 2u, 3u}) {
    // Random grains: a 12 x 12 grid of squares, each phase 1 with probability 0.4.
    std::mt19937 rng(seed);
    std::bernoulli_distribution coin(0.4);
    std::vector<bool> grain(144);
    for (auto&& g : grain) g = coin(rng);
    const auto phase_of = [&](const Eigen::Vector2d& c) {
      return static_cast<bool>(grain[static_cast<int>(c.x() * 12) + 12 * static_cast<int>(c.y() * 12)]);
    };
    double f1 = 0.0;
    const LinearHomogenization h = homogenize_two_phase(mesh, A, phase_of, E0, nu0, E1, nu1, &f1);
    // Voigt and Reuss (Hill 1952): C_Reuss <= C^H <= C_Voigt as quadratic forms, any geometry.
    const Matrix C0 = isotropic_stiffness(2, E0, nu0), C1 = isotropic_stiffness(2, E1, nu1);
    const Matrix voigt = (1.0 - f1) * C0 + f1 * C1;
    const Matrix reuss = ((1.0 - f1) * C0.inverse() + f1 * C1.inverse()).inverse();
    EXPECT_GT(symmetric_eigenvalues(voigt - h.stiffness).minCoeff(), 0.0);
    EXPECT_GT(symmetric_eigenvalues(h.stiffness - reuss).minCoeff(), 0.0);
    // HS on the cell's bulk modulus under hydrostatic strain (upper) and stress (lower), and
    // on the shear moduli averaged over the square's two shear modes.
    const Matrix& C = h.stiffness;
    const Matrix S = compliance(C);
    const double k_strain = (C(0, 0) + C(1, 1) + 2.0 * C(0, 1)) / 4.0;
    const double k_stress = 1.0 / (S(0, 0) + S(1, 1) + 2.0 * S(0, 1));
    const double mu_mean = 0.5 * (C(2, 2) + (C(0, 0) + C(1, 1) - 2.0 * C(0, 1)) / 4.0);
    const Moduli lower = hashin_shtrikman(soft, stiff, f1), upper = hashin_shtrikman(stiff, soft, 1.0 - f1);
    EXPECT_LT(lower.k, k_stress) << "seed " << seed;
    EXPECT_LT(k_strain, upper.k) << "seed " << seed;
    EXPECT_LT(lower.mu, mu_mean) << "seed " << seed;
    EXPECT_LT(mu_mean, upper.mu) << "seed " << seed;
    std::printf("seed %u: f1 = %.3f  k in [%.4f, %.4f] (HS [%.4f, %.4f]);  mu %.4f (HS [%.4f, %.4f])\n", seed,
                f1, k_stress, k_strain, lower.k, upper.k, mu_mean, lower.mu, upper.mu);
  }
}

TEST(GradedCell, TensorConvergesUnderRefinement) {
  // A smoothly graded cell, E(X) = 5.5 + 4.5 cos(2 pi x) cos(2 pi y) sampled at element
  // centroids: no interface staircase, so C^H converges at the P1 energy rate O(h^2) (the
  // effective tensor is an energy; Ciarlet, The Finite Element Method for Elliptic Problems,
  // thm 3.2.2 with the Aubin-Nitsche argument). A pixelated sharp inclusion converges only at
  // O(h) and not monotonically, so it makes a poor rate study.
  const Eigen::Matrix2d A = Eigen::Matrix2d::Identity();
  std::vector<Matrix> C;
  for (const int n : {8, 16, 32, 64}) {
    const Mesh mesh = lattice_triangle_mesh(A, Eigen::Vector2d::Zero(), n, n, TriangleSplit::crossed);
    LinearCell cell(make_box_periodic_cell(mesh));
    const int ne = mesh.num_elements();
    Vector E(ne);
    for (int e = 0; e < ne; ++e) {
      Eigen::Vector2d c = Eigen::Vector2d::Zero();
      for (int a = 0; a < 3; ++a) c += mesh.rest_positions.row(mesh.elements(e, a)).transpose() / 3.0;
      E[e] = 5.5 + 4.5 * std::cos(2.0 * M_PI * c.x()) * std::cos(2.0 * M_PI * c.y());
    }
    C.push_back(cell.solve(E, Vector::Constant(ne, 0.3)).stiffness);
  }
  std::vector<double> rates;
  for (std::size_t k = 0; k + 2 < C.size(); ++k) {
    const double d1 = (C[k + 1] - C[k]).norm(), d2 = (C[k + 2] - C[k + 1]).norm();
    rates.push_back(std::log2(d1 / d2));
    std::printf("|C_%d - C_%d| = %.3e, next %.3e, observed rate %.2f\n", 16 << k, 8 << k, d1, d2,
                rates.back());
  }
  for (const double r : rates) EXPECT_GT(r, 1.8);
  EXPECT_LT((C[3] - C[2]).norm() / C[3].norm(), 1e-3);
}

TEST(TwoPhaseCell, MirrorSymmetricCellIsOrthotropic) {
  // A centred rectangular inclusion on the crossed (mirror-symmetric) mesh: the cell is
  // symmetric under x -> 1 - x and y -> 1 - y, so the normal-shear couplings C_13 and C_23
  // vanish (orthotropy; e.g. Nye, Physical Properties of Crystals, ch. VIII).
  const Eigen::Matrix2d A = Eigen::Vector2d(1.0, 0.8).asDiagonal();
  const auto phase_of = [](const Eigen::Vector2d& c) {
    return std::abs(c.x() - 0.5) < 0.3 && std::abs(c.y() - 0.4) < 0.15;
  };
  const Matrix C =
      homogenize_two_phase(lattice_triangle_mesh(A, Eigen::Vector2d::Zero(), 10, 8, TriangleSplit::crossed),
                           A, phase_of, 1.0, 0.3, 50.0, 0.2)
          .stiffness;
  EXPECT_LT(std::abs(C(0, 2)), 1e-13 * C.norm());
  EXPECT_LT(std::abs(C(1, 2)), 1e-13 * C.norm());
  EXPECT_GT(std::abs(C(0, 0) - C(1, 1)), 1e-3 * C.norm());  // but not isotropic
}

TEST(TwoPhaseCell, HexagonalCellIsIsotropicInPlane) {
  // A disc inclusion at the centre of a 60-degree rhombic cell meshed with equilateral
  // triangles: the cell has 6-fold rotational symmetry, and a 2D fourth-order elasticity
  // tensor with 3- or 6-fold symmetry is isotropic (Nye, ch. VIII; Hermann's theorem), so
  // C11 = C22, C66 = (C11 - C12) / 2, C16 = C26 = 0 and E(d) is constant.
  Eigen::Matrix2d A;
  A << 1.0, 0.5, 0.0, std::sqrt(3.0) / 2.0;
  const Eigen::Vector2d centre = A * Eigen::Vector2d(0.5, 0.5);
  const auto phase_of = [&](const Eigen::Vector2d& c) { return periodic_distance(c, centre, A) < 0.3; };
  const Matrix C =
      homogenize_two_phase(lattice_triangle_mesh(A, Eigen::Vector2d::Zero(), 12, 12, TriangleSplit::backward),
                           A, phase_of, 1.0, 0.3, 0.01, 0.3)
          .stiffness;
  const double scale = C.norm();
  EXPECT_LT(std::abs(C(0, 0) - C(1, 1)), 1e-12 * scale) << C;
  EXPECT_LT(std::abs(C(2, 2) - 0.5 * (C(0, 0) - C(0, 1))), 1e-12 * scale) << C;
  EXPECT_LT(std::abs(C(0, 2)), 1e-12 * scale);
  EXPECT_LT(std::abs(C(1, 2)), 1e-12 * scale);
  const Matrix S = compliance(C);
  const double E0 = directional_youngs_modulus(S, plane_direction(2, 0, 1, 0.0));
  for (const double theta : {0.3, 0.7, 1.1})
    EXPECT_NEAR(directional_youngs_modulus(S, plane_direction(2, 0, 1, theta)), E0, 1e-12 * E0);
  // The same disc in a square cell is not isotropic (the test can fail).
  const Eigen::Matrix2d square = Eigen::Matrix2d::Identity();
  const Matrix Cs =
      homogenize_two_phase(
          lattice_triangle_mesh(square, Eigen::Vector2d::Zero(), 12, 12, TriangleSplit::crossed), square,
          [&](const Eigen::Vector2d& c) {
            return periodic_distance(c, Eigen::Vector2d(0.5, 0.5), square) < 0.3;
          },
          1.0, 0.3, 0.01, 0.3)
          .stiffness;
  EXPECT_GT(std::abs(Cs(2, 2) - 0.5 * (Cs(0, 0) - Cs(0, 1))), 1e-3 * Cs.norm());
}

}  // namespace
}  // namespace tailor::two_phase_cell_test
