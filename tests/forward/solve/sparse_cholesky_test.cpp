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

// An arrow matrix (vertex 0 coupled to every other) fills L completely in the natural order;
// a fill-reducing ordering eliminates the hub last, with no fill: nnz(L) = 2n - 1.
TEST(SparseCholesky, EstimatedFactorCostOfEachOrdering) {
  const int n = 40;
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) t.emplace_back(i, i, 2.0 * n);
  for (int i = 1; i < n; ++i) t.emplace_back(0, i, -1.0);
  SparseMatrix arrow(n, n);
  arrow.setFromTriplets(t.begin(), t.end());
  arrow.makeCompressed();
  for (const FillOrdering ordering : {FillOrdering::amd, FillOrdering::metis, FillOrdering::nesdis}) {
    const auto [nonzeros, flops] = estimate_factor_cost(arrow, ordering);
    EXPECT_EQ(nonzeros, 2.0 * n - 1.0);
    EXPECT_GT(flops, 0.0);
    EXPECT_LT(flops, 20.0 * n);  // the natural order's complete fill would take O(n^3)
  }
  EXPECT_THROW(estimate_factor_cost(SparseMatrix(3, 4), FillOrdering::amd), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::sparse_cholesky_test
