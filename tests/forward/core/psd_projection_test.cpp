// forward/core/psd_projection.hpp: the one PSD projection of the tree. References: a 2x2 case in
// closed form, and for larger matrices the characterization of the Frobenius-nearest PSD matrix
// (Higham 1988): P is PSD, has eigenvalues max(lambda_i(A), 0), and ||A - P||_F equals the norm of
// A's negative eigenvalues (Hoffman-Wielandt makes that distance the least any PSD matrix can
// reach). The characterization is shown to reject a wrong projection.
#include "forward/core/psd_projection.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "forward/core/symmetric_eigen.hpp"

namespace tailor::psd_projection_test {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

MatrixXd random_symmetric(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  MatrixXd B(n, n);
  for (int i = 0; i < n * n; ++i) B.data()[i] = u(rng);
  return 0.5 * (B + B.transpose());
}

// Relative deviation of P from the nearest PSD matrix to A (0 for the exact projection).
double distance_from_projection(const MatrixXd& A, const MatrixXd& P) {
  const VectorXd lambda = symmetric_eigenvalues(A);
  const VectorXd clamped = lambda.cwiseMax(0.0);
  const double scale = std::max(lambda.cwiseAbs().maxCoeff(), 1e-300);
  const double symmetry = (P - P.transpose()).norm();
  const double spectrum = (symmetric_eigenvalues(P) - clamped).norm();  // both ascending
  const double distance = std::abs((A - P).norm() - (lambda - clamped).norm());
  return (symmetry + spectrum + distance) / scale;
}

TEST(PsdProjection, TwoByTwoInClosedForm) {
  // [[1, 2], [2, 1]] has eigenpairs 3 (1, 1)/sqrt2 and -1 (1, -1)/sqrt2: the projection is
  // 3 v v^T = 1.5 [[1, 1], [1, 1]].
  Eigen::Matrix2d A;
  A << 1.0, 2.0, 2.0, 1.0;
  EXPECT_FALSE(cholesky_accepts<2>(A));
  EXPECT_TRUE(project_psd<2>(A));
  EXPECT_LT((A - Eigen::Matrix2d::Constant(1.5)).norm(), 1e-14);
  // A zero diagonal with a coupling: eigenvalues +-1, projection 0.5 [[1, 1], [1, 1]].
  Eigen::Matrix2d C;
  C << 0.0, 1.0, 1.0, 0.0;
  EXPECT_TRUE(project_psd<2>(C));
  EXPECT_LT((C - Eigen::Matrix2d::Constant(0.5)).norm(), 1e-14);
}

TEST(PsdProjection, PsdMatricesAreLeftUntouched) {
  for (unsigned seed = 0; seed < 5; ++seed) {
    const MatrixXd B = random_symmetric(9, seed);
    Eigen::Matrix<double, 9, 9> A = B * B.transpose();  // positive definite
    const Eigen::Matrix<double, 9, 9> before = A;
    EXPECT_TRUE(cholesky_accepts<9>(A));
    EXPECT_FALSE(project_psd<9>(A));
    EXPECT_EQ(A, before);  // bit for bit: the fast path does not round-trip through eigenvectors
  }
  // Exactly singular PSD (rank 2 of 12, like rigid modes at rest) and the zero matrix pass too.
  const MatrixXd V = random_symmetric(12, 7).leftCols(2);
  Eigen::Matrix<double, 12, 12> singular = V * V.transpose();
  const Eigen::Matrix<double, 12, 12> before = singular;
  EXPECT_FALSE(project_psd<12>(singular));
  EXPECT_EQ(singular, before);
  Eigen::Matrix3d zero = Eigen::Matrix3d::Zero();
  EXPECT_TRUE(cholesky_accepts<3>(zero));
  EXPECT_FALSE(project_psd<3>(zero));
  EXPECT_TRUE(zero.isZero(0.0));
}

TEST(PsdProjection, TheShiftSeparatesRoundOffFromNegativeCurvature) {
  // An eigenvalue of -1e-14 against a scale of 1 is round-off (kPsdShift = 1e-12): kept. One of
  // -1e-10 is curvature: clamped to 0.
  Eigen::Matrix2d round_off = Eigen::Vector2d(1.0, -1e-14).asDiagonal();
  EXPECT_FALSE(project_psd<2>(round_off));
  EXPECT_EQ(round_off(1, 1), -1e-14);
  Eigen::Matrix2d negative = Eigen::Vector2d(1.0, -1e-10).asDiagonal();
  EXPECT_TRUE(project_psd<2>(negative));
  EXPECT_LT((negative - Eigen::Matrix2d(Eigen::Vector2d(1.0, 0.0).asDiagonal())).norm(), 1e-15);
}

TEST(PsdProjection, IndefiniteMatricesGoToTheNearestPsdMatrix) {
  for (unsigned seed = 0; seed < 10; ++seed) {
    const MatrixXd A = random_symmetric(9, 100 + seed);
    Eigen::Matrix<double, 9, 9> P = A;
    EXPECT_TRUE(project_psd<9>(P));
    EXPECT_LT(distance_from_projection(A, P), 1e-12) << "seed " << seed;
    EXPECT_GE(symmetric_eigenvalues(P).minCoeff(), -1e-12 * A.norm());
    EXPECT_FALSE(project_psd<9>(P)) << "a projection is idempotent";
  }
}

TEST(PsdProjection, DynamicAndLargeSizes) {
  // A run-time size, and one above the 32 x 32 stack copy of the Cholesky test.
  for (const int n : {5, 40}) {
    const MatrixXd A = random_symmetric(n, 31u + static_cast<unsigned>(n));
    MatrixXd P = A;
    EXPECT_TRUE(project_psd(P));
    EXPECT_LT(distance_from_projection(A, P), 1e-12) << "n = " << n;
    MatrixXd D = A + (2.0 * A.norm()) * MatrixXd::Identity(n, n);  // diagonally shifted: PD
    const MatrixXd before = D;
    EXPECT_FALSE(project_psd(D));
    EXPECT_EQ(D, before);
  }
}

TEST(PsdProjection, TheReferenceRejectsAWrongProjection) {
  const MatrixXd A = random_symmetric(6, 3);
  MatrixXd P = A;
  ASSERT_TRUE(project_psd(P));
  ASSERT_LT(distance_from_projection(A, P), 1e-12);
  // PSD but not the nearest: the diagonal shift A + |lambda_min| I.
  const MatrixXd shifted = A - symmetric_eigenvalues(A).minCoeff() * MatrixXd::Identity(6, 6);
  EXPECT_GT(distance_from_projection(A, shifted), 1e-2);
  // The right spectrum on the wrong eigenvectors: P with two coordinates swapped.
  MatrixXd swapped = P;
  swapped.row(0).swap(swapped.row(1));
  swapped.col(0).swap(swapped.col(1));
  EXPECT_GT(distance_from_projection(A, swapped), 1e-2);
}

TEST(PsdProjection, NaNIsNeverHiddenBehindAFiniteMatrix) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
  A(0, 1) = A(1, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(cholesky_accepts<3>(A));
  project_psd<3>(A);
  EXPECT_FALSE(A.allFinite());
  Eigen::Matrix3d diagonal = Eigen::Matrix3d::Identity();
  diagonal(2, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(cholesky_accepts<3>(diagonal));
  project_psd<3>(diagonal);
  EXPECT_FALSE(diagonal.allFinite());
}

}  // namespace
}  // namespace tailor::psd_projection_test
