#include "forward/reduction/generalized_eigen.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "forward/core/symmetric_eigen.hpp"

namespace tailor::generalized_eigen_test {
namespace {

// Graph Laplacian of the path 0 - 1 - ... - (n-1), unit weights (singular: constants).
SparseMatrix path_laplacian(int n) {
  Triplets t;
  for (int i = 0; i + 1 < n; ++i) {
    t.emplace_back(i, i, 1.0);
    t.emplace_back(i + 1, i + 1, 1.0);
    t.emplace_back(i, i + 1, -1.0);
    t.emplace_back(i + 1, i, -1.0);
  }
  SparseMatrix a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

// tridiag(-1, 2, -1): 1D Dirichlet stiffness, positive definite.
SparseMatrix dirichlet_1d(int n) {
  Triplets t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 2.0);
    if (i + 1 < n) {
      t.emplace_back(i, i + 1, -1.0);
      t.emplace_back(i + 1, i, -1.0);
    }
  }
  SparseMatrix a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

SparseMatrix diagonal(const Vector& d) {
  SparseMatrix b(d.size(), d.size());
  Triplets t;
  for (Eigen::Index i = 0; i < d.size(); ++i) t.emplace_back(static_cast<int>(i), static_cast<int>(i), d[i]);
  b.setFromTriplets(t.begin(), t.end());
  return b;
}

Vector wavy_masses(int n) {
  Vector d(n);
  for (int i = 0; i < n; ++i) d[i] = 1.0 + 0.5 * std::sin(0.37 * i) + 0.01 * i;
  return d;
}

void expect_pairs_valid(const SparseMatrix& a, const SparseMatrix& b, const GeneralizedEigenResult& r) {
  ASSERT_TRUE(r.success) << r.message;
  const Eigen::Index k = r.eigenvalues.size();
  ASSERT_EQ(r.eigenvectors.cols(), k);
  const Matrix gram = r.eigenvectors.transpose() * (b * r.eigenvectors);
  EXPECT_LT((gram - Matrix::Identity(k, k)).cwiseAbs().maxCoeff(), 1e-10);
  for (Eigen::Index j = 0; j < k; ++j) {
    if (j > 0) {
      EXPECT_LE(r.eigenvalues[j - 1], r.eigenvalues[j]);
    }
    const Vector x = r.eigenvectors.col(j);
    const double scale = std::max(1.0, std::abs(r.eigenvalues[j]));
    EXPECT_LT((a * x - r.eigenvalues[j] * (b * x)).norm(), 1e-9 * scale) << "pair " << j;
  }
}

TEST(GeneralizedEigen, PathGraphLaplacianMatchesClosedForm) {
  const int n = 200, count = 6;
  const SparseMatrix a = path_laplacian(n);
  const SparseMatrix b = diagonal(Vector::Ones(n));
  const GeneralizedEigenResult r = generalized_eigenpairs(a, b, count);
  expect_pairs_valid(a, b, r);
  EXPECT_FALSE(r.dense);
  EXPECT_LT(r.shift, 0.0);
  EXPECT_EQ(r.converged, count);
  EXPECT_GT(r.iterations, 0);
  for (int k = 0; k < count; ++k)
    EXPECT_NEAR(r.eigenvalues[k], 2.0 - 2.0 * std::cos(k * std::numbers::pi / n), 1e-12) << "k = " << k;
  // The null vector of the singular Laplacian is the constant, 1 / sqrt(n) in the B = I norm.
  EXPECT_LT((r.eigenvectors.col(0) - Vector::Constant(n, 1.0 / std::sqrt(n))).norm(), 1e-10);
  // Second mode: cos(pi (i + 1/2) / n), normalised (sign fixed by the largest entry).
  Vector c(n);
  for (int i = 0; i < n; ++i) c[i] = std::cos(std::numbers::pi * (i + 0.5) / n);
  c.normalize();
  EXPECT_NEAR(std::abs(c.dot(r.eigenvectors.col(1))), 1.0, 1e-10);
}

TEST(GeneralizedEigen, DiagonalMassMatchesDenseSolver) {
  const int n = 150, count = 5;
  const SparseMatrix a = dirichlet_1d(n);
  const SparseMatrix b = diagonal(wavy_masses(n));
  const GeneralizedEigenResult r = generalized_eigenpairs(a, b, count);
  expect_pairs_valid(a, b, r);
  EXPECT_FALSE(r.dense);
  // Reference: Eigen's dense GeneralizedSelfAdjointEigenSolver (forward/core/symmetric_eigen).
  Vector dense_values;
  Matrix dense_vectors;
  ASSERT_TRUE(generalized_symmetric_eigen(Matrix(a), Matrix(b), dense_values, dense_vectors));
  for (int k = 0; k < count; ++k) {
    EXPECT_NEAR(r.eigenvalues[k], dense_values[k], 1e-10 * dense_values[k]) << "k = " << k;
    // Simple eigenvalues: the B-normalised vectors agree up to sign.
    const double overlap = dense_vectors.col(k).dot(b * r.eigenvectors.col(k));
    EXPECT_NEAR(std::abs(overlap), 1.0, 1e-9) << "k = " << k;
  }
}

TEST(GeneralizedEigen, SingularLaplacianWithNonIdentityMassNeedsTheShift) {
  const int n = 300, count = 4;
  const SparseMatrix a = path_laplacian(n);
  const Vector masses = wavy_masses(n);
  const SparseMatrix b = diagonal(masses);
  const GeneralizedEigenResult r = generalized_eigenpairs(a, b, count);
  expect_pairs_valid(a, b, r);
  EXPECT_NEAR(r.eigenvalues[0], 0.0, 1e-12);
  // Constant mode, B-normalised: 1 / sqrt(sum of masses).
  EXPECT_LT(
      (r.eigenvectors.col(0) - Vector::Constant(n, 1.0 / std::sqrt(masses.sum()))).cwiseAbs().maxCoeff(),
      1e-10);
  Vector dense_values;
  Matrix dense_vectors;
  ASSERT_TRUE(generalized_symmetric_eigen(Matrix(a), Matrix(b), dense_values, dense_vectors));
  for (int k = 1; k < count; ++k)
    EXPECT_NEAR(r.eigenvalues[k], dense_values[k], 1e-10 * dense_values[k]) << "k = " << k;
}

TEST(GeneralizedEigen, ExplicitShiftOnPositiveDefiniteProblem) {
  const int n = 120, count = 3;
  const SparseMatrix a = dirichlet_1d(n);
  const SparseMatrix b = diagonal(Vector::Ones(n));
  GeneralizedEigenOptions options;
  options.shift = 0.0;
  const GeneralizedEigenResult r = generalized_eigenpairs(a, b, count, options);
  expect_pairs_valid(a, b, r);
  EXPECT_EQ(r.shift, 0.0);
  for (int k = 1; k <= count; ++k)
    EXPECT_NEAR(r.eigenvalues[k - 1], 2.0 - 2.0 * std::cos(k * std::numbers::pi / (n + 1)), 1e-12);
}

TEST(GeneralizedEigen, SmallProblemsFallBackToDense) {
  const int n = 10;
  const SparseMatrix a = path_laplacian(n);
  const SparseMatrix b = diagonal(Vector::Ones(n));
  for (int count : {3, n - 1}) {
    const GeneralizedEigenResult r = generalized_eigenpairs(a, b, count);
    expect_pairs_valid(a, b, r);
    EXPECT_TRUE(r.dense);
    EXPECT_NE(r.message.find("dense"), std::string::npos) << r.message;
    for (int k = 0; k < count; ++k)
      EXPECT_NEAR(r.eigenvalues[k], 2.0 - 2.0 * std::cos(k * std::numbers::pi / n), 1e-12);
  }
  // count = n - 1 on a problem above the threshold also goes dense.
  const int big = 80;
  const GeneralizedEigenResult r =
      generalized_eigenpairs(path_laplacian(big), diagonal(Vector::Ones(big)), big - 1);
  EXPECT_TRUE(r.dense);
  expect_pairs_valid(path_laplacian(big), diagonal(Vector::Ones(big)), r);
}

TEST(GeneralizedEigen, InvalidInputsThrow) {
  const SparseMatrix a = path_laplacian(100), b = diagonal(Vector::Ones(100));
  EXPECT_THROW(generalized_eigenpairs(SparseMatrix(100, 99), b, 3), std::invalid_argument);
  EXPECT_THROW(generalized_eigenpairs(a, diagonal(Vector::Ones(99)), 3), std::invalid_argument);
  EXPECT_THROW(generalized_eigenpairs(a, b, 0), std::invalid_argument);
  EXPECT_THROW(generalized_eigenpairs(a, b, 100), std::invalid_argument);
  EXPECT_THROW(generalized_eigenpairs(a, b, -2), std::invalid_argument);
  GeneralizedEigenOptions bad_ncv;
  bad_ncv.ncv = 3;
  EXPECT_THROW(generalized_eigenpairs(a, b, 3, bad_ncv), std::invalid_argument);
  GeneralizedEigenOptions bad_tol;
  bad_tol.tolerance = -1.0;
  EXPECT_THROW(generalized_eigenpairs(a, b, 3, bad_tol), std::invalid_argument);
  GeneralizedEigenOptions bad_iter;
  bad_iter.max_iterations = 0;
  EXPECT_THROW(generalized_eigenpairs(a, b, 3, bad_iter), std::invalid_argument);
}

TEST(GeneralizedEigen, IterationLimitReportsInsteadOfAborting) {
  const int n = 400, count = 10;
  GeneralizedEigenOptions options;
  options.max_iterations = 1;
  options.ncv = 11;
  const GeneralizedEigenResult r =
      generalized_eigenpairs(path_laplacian(n), diagonal(wavy_masses(n)), count, options);
  // One restart cannot converge ten pairs: reported, not thrown or aborted.
  EXPECT_FALSE(r.success);
  EXPECT_LT(r.converged, count);
  EXPECT_NE(r.message.find("iterations"), std::string::npos) << r.message;
}


// A square grid's Laplacian has repeated eigenvalues (the x and y waves): the basis ARPACK
// returns for such an eigenspace depends on the start vector, so two calls in one process must
// start alike and give the same vectors, or the same scene would give another design space.
TEST(GeneralizedEigen, RepeatedEigenvaluesGiveTheSameVectorsEveryCall) {
  const int side = 20, n = side * side;
  Triplets entries;  // 5-point Laplacian, zero Dirichlet values around the grid
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j) {
      const int k = i * side + j;
      entries.emplace_back(k, k, 4.0);
      if (i > 0) entries.emplace_back(k, k - side, -1.0);
      if (i + 1 < side) entries.emplace_back(k, k + side, -1.0);
      if (j > 0) entries.emplace_back(k, k - 1, -1.0);
      if (j + 1 < side) entries.emplace_back(k, k + 1, -1.0);
    }
  SparseMatrix grid(n, n);
  grid.setFromTriplets(entries.begin(), entries.end());
  const SparseMatrix b = diagonal(Vector::Ones(n));
  const GeneralizedEigenResult first = generalized_eigenpairs(grid, b, 6);
  const GeneralizedEigenResult second = generalized_eigenpairs(grid, b, 6);
  ASSERT_TRUE(first.success && second.success) << first.message << " / " << second.message;
  ASSERT_FALSE(first.dense);
  EXPECT_NEAR(first.eigenvalues[1], first.eigenvalues[2], 1e-10 * first.eigenvalues[2]);  // repeated
  EXPECT_EQ((first.eigenvectors - second.eigenvectors).cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
}  // namespace tailor::generalized_eigen_test
