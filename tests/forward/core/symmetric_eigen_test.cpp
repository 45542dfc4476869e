// forward/core/symmetric_eigen.hpp: one compiled decomposition for fixed and run-time sizes, and
// the compiled-once QR solve and orthonormal basis.
// References: a 2x2 case in closed form, and for larger matrices the defining properties
// (A V = V diag(lambda), V^T V = I, lambda ascending) and the trace and Frobenius norm, which
// equal the sum of the eigenvalues and the norm of the eigenvalue vector.
#include "forward/core/symmetric_eigen.hpp"

#include <gtest/gtest.h>

#include <random>

namespace tailor::symmetric_eigen_test {
namespace {

template <int N>
Eigen::Matrix<double, N, N> random_symmetric(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Matrix<double, N, N> B(n, n);
  for (int i = 0; i < n * n; ++i) B.data()[i] = u(rng);
  return 0.5 * (B + B.transpose());
}

template <int N>
void expect_decomposes(const Eigen::Matrix<double, N, N>& A) {
  Eigen::Matrix<double, N, 1> lambda;
  Eigen::Matrix<double, N, N> V;
  symmetric_eigen(A, lambda, V);
  const int n = static_cast<int>(A.rows());
  const double scale = A.norm();
  EXPECT_LT((A * V - V * lambda.asDiagonal()).norm(), 1e-13 * scale) << "n = " << n;
  EXPECT_LT((V.transpose() * V - Eigen::MatrixXd::Identity(n, n)).norm(), 1e-13) << "n = " << n;
  for (int i = 1; i < n; ++i) EXPECT_LE(lambda[i - 1], lambda[i]) << "ascending, n = " << n;
  EXPECT_NEAR(lambda.sum(), A.trace(), 1e-13 * scale);
  EXPECT_NEAR(lambda.norm(), scale, 1e-13 * scale);
  // The values-only form agrees with the full one.
  EXPECT_LT((symmetric_eigenvalues(A) - Eigen::VectorXd(lambda)).norm(), 1e-13 * scale);
}

TEST(SymmetricEigen, TwoByTwoInClosedForm) {
  // [[2, 1], [1, 2]]: eigenvalues 1 and 3 with eigenvectors (1, -1)/sqrt2 and (1, 1)/sqrt2.
  Eigen::Matrix2d A;
  A << 2.0, 1.0, 1.0, 2.0;
  Eigen::Vector2d lambda;
  Eigen::Matrix2d V;
  symmetric_eigen(A, lambda, V);
  EXPECT_NEAR(lambda[0], 1.0, 1e-15);
  EXPECT_NEAR(lambda[1], 3.0, 1e-15);
  EXPECT_NEAR(std::abs(V.col(0).dot(Eigen::Vector2d(1.0, -1.0).normalized())), 1.0, 1e-15);
  EXPECT_NEAR(std::abs(V.col(1).dot(Eigen::Vector2d(1.0, 1.0).normalized())), 1.0, 1e-15);
}

TEST(SymmetricEigen, FixedAndRunTimeSizes) {
  expect_decomposes<2>(random_symmetric<2>(2, 1));
  expect_decomposes<4>(random_symmetric<4>(4, 2));
  expect_decomposes<9>(random_symmetric<9>(9, 3));
  for (const int n : {1, 3, 12, 40})
    expect_decomposes<Eigen::Dynamic>(random_symmetric<Eigen::Dynamic>(n, 4u + n));
}

TEST(SymmetricEigen, RepeatedEigenvaluesKeepAnOrthonormalBasis) {
  // diag(2, 2, 5) rotated: a double eigenvalue, whose eigenvectors are any basis of a plane.
  const Eigen::Matrix3d Q = orthonormal_columns(random_symmetric<Eigen::Dynamic>(3, 9), 3);
  const Eigen::Matrix3d A = Q * Eigen::Vector3d(2.0, 2.0, 5.0).asDiagonal() * Q.transpose();
  expect_decomposes<3>(A);
  EXPECT_LT((symmetric_eigenvalues(A) - Eigen::Vector3d(2.0, 2.0, 5.0)).norm(), 1e-14);
}

TEST(SymmetricEigen, TheChecksSeeAWrongDecomposition) {
  const Eigen::Matrix3d A = random_symmetric<3>(3, 11);
  Eigen::Vector3d lambda;
  Eigen::Matrix3d V;
  symmetric_eigen(A, lambda, V);
  // Eigenvectors paired with the wrong eigenvalues fail the defining equation.
  const Eigen::Vector3d reversed = lambda.reverse();
  EXPECT_GT((A * V - V * reversed.asDiagonal()).norm(), 1e-3 * A.norm());
}


// pivoted_qr_solve: the least-squares solution satisfies the normal equations A^T (A x - b) = 0
// (a solution moved by 1e-3 does not), and the rank of a matrix with a dependent column is found.
TEST(DenseQr, PivotedSolveIsTheLeastSquaresSolutionAndFindsTheRank) {
  const Eigen::MatrixXd A = random_symmetric<Eigen::Dynamic>(6, 21).leftCols(3);
  const Eigen::VectorXd b = random_symmetric<Eigen::Dynamic>(6, 22).col(0);
  const PivotedQrSolution full = pivoted_qr_solve(A, b);
  EXPECT_EQ(full.rank, 3);
  EXPECT_LT((A.transpose() * (A * full.x - b)).norm(), 1e-12 * A.norm() * b.norm());
  const Eigen::VectorXd moved = full.x.col(0) + 1e-3 * Eigen::Vector3d(1.0, -1.0, 0.5);
  EXPECT_GT((A.transpose() * (A * moved - b)).norm(), 1e-6 * A.norm() * b.norm());
  Eigen::MatrixXd D = A;
  D.col(2) = D.col(0) + 2.0 * D.col(1);  // rank 2
  const Eigen::VectorXd consistent = D * Eigen::Vector3d(1.0, 2.0, 3.0);
  const PivotedQrSolution deficient = pivoted_qr_solve(D, consistent);
  EXPECT_EQ(deficient.rank, 2);
  EXPECT_LT((D * deficient.x - consistent).norm(), 1e-12 * consistent.norm());
}

// orthonormal_columns: Q^T Q = I and Q Q^T A = A (Q spans A's columns).
TEST(DenseQr, OrthonormalColumnsSpanTheMatrixsColumns) {
  const Eigen::MatrixXd A = random_symmetric<Eigen::Dynamic>(7, 23).leftCols(3);
  const Eigen::MatrixXd Q = orthonormal_columns(A, 3);
  ASSERT_EQ(Q.rows(), 7);
  ASSERT_EQ(Q.cols(), 3);
  EXPECT_LT((Q.transpose() * Q - Eigen::Matrix3d::Identity()).norm(), 1e-14);
  EXPECT_LT((Q * (Q.transpose() * A) - A).norm(), 1e-13 * A.norm());
}

}  // namespace
}  // namespace tailor::symmetric_eigen_test
