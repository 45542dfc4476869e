#include "forward/solve/sparse_cholesky.hpp"

#include <gtest/gtest.h>

#include "../../support/quadratic_term.hpp"

namespace tailor::sparse_cholesky_test {
namespace {

SparseMatrix upper(const SparseMatrix& full) {
  SparseMatrix u = full.triangularView<Eigen::Upper>();
  u.makeCompressed();
  return u;
}

TEST(SparseCholesky, SolvesPositiveDefiniteSystem) {
  const SparseMatrix A = testing::random_spd(60, 3);
  const Vector x_true = Vector::LinSpaced(60, -1.0, 1.0);
  SparseCholesky chol;
  const auto r = chol.factorize(upper(A));
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_TRUE(r.positive_definite);
  EXPECT_FALSE(chol.is_ldlt());
  EXPECT_LT((chol.solve(Vector(A * x_true)) - x_true).norm(), 1e-10);
}

TEST(SparseCholesky, FallsBackToLdltAndCountsNegativePivots) {
  // diag(4, -3, 2, -1, 5) plus a coupling that keeps leading minors nonzero: two negative
  // eigenvalues, so two negative pivots (Sylvester's law of inertia).
  Triplets t = {{0, 0, 4}, {1, 1, -3}, {2, 2, 2}, {3, 3, -1}, {4, 4, 5}, {0, 1, 0.5}, {1, 0, 0.5}, {2, 4, 0.3}, {4, 2, 0.3}};
  SparseMatrix A(5, 5);
  A.setFromTriplets(t.begin(), t.end());
  SparseCholesky chol;
  const auto r = chol.factorize(upper(A));
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_FALSE(r.positive_definite);
  EXPECT_TRUE(chol.is_ldlt());
  EXPECT_EQ(r.negative_pivots, 2);
  const Vector x_true = Vector::LinSpaced(5, 1.0, 2.0);
  EXPECT_LT((chol.solve(Vector(A * x_true)) - x_true).norm(), 1e-12);
  // The same object goes back to LL^T for a positive definite matrix with the same pattern.
  for (int i = 0; i < 5; ++i) A.coeffRef(i, i) = 10.0;
  const auto r2 = chol.factorize(upper(A));
  EXPECT_TRUE(r2.positive_definite);
  EXPECT_LT((chol.solve(Vector(A * x_true)) - x_true).norm(), 1e-12);
}

TEST(SparseCholesky, ReportsSingularMatrix) {
  Triplets t = {{0, 0, 1}, {1, 1, 0}, {2, 2, 1}};
  SparseMatrix A(3, 3);
  A.setFromTriplets(t.begin(), t.end());
  SparseCholesky chol;
  const auto r = chol.factorize(upper(A));
  EXPECT_FALSE(r.success);
  EXPECT_NE(r.message.find("singular"), std::string::npos) << r.message;
  EXPECT_THROW(chol.solve(Vector::Ones(3)), std::logic_error);
}

}  // namespace
}  // namespace tailor::sparse_cholesky_test
