// The low-rank Hessian hook: SparseCholesky with a Woodbury update solves (A + F G F^T) x = b
// like a dense solver does (G indefinite), and factorize() drops the update.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "damping_fixture.hpp"
#include "forward/solve/sparse_cholesky.hpp"

namespace tailor::low_rank_hessian_test {
namespace {

using namespace tailor::testing;

TEST(LowRankHessian, WoodburySolveMatchesDense) {
  const int n = 40, k = 4;
  Triplets t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 4.0 + 0.1 * i);
    if (i + 1 < n) t.emplace_back(i, i + 1, -1.0);
  }
  SparseMatrix upper(n, n);
  upper.setFromTriplets(t.begin(), t.end());
  upper.makeCompressed();
  Matrix F(n, k);
  for (int j = 0; j < k; ++j) F.col(j) = random_vector(n, 50 + j, 1.0);
  Matrix G = Matrix::Zero(k, k);
  G.diagonal() << 0.5, -0.05, 2.0, 0.0;
  G(0, 1) = G(1, 0) = 0.1;
  const Matrix dense = Matrix(SparseMatrix(upper.selfadjointView<Eigen::Upper>())) + F * G * F.transpose();
  const Vector b = random_vector(n, 60, 1.0);
  SparseCholesky chol;
  ASSERT_TRUE(chol.factorize(upper).success);
  chol.set_low_rank_update(F, G);
  EXPECT_TRUE(chol.has_low_rank_update());
  const Vector x = chol.solve(b);
  EXPECT_LT((dense * x - b).norm(), 1e-10 * b.norm());
  ASSERT_TRUE(chol.factorize(upper).success);
  EXPECT_FALSE(chol.has_low_rank_update());
  EXPECT_LT((Matrix(SparseMatrix(upper.selfadjointView<Eigen::Upper>())) * chol.solve(b) - b).norm(),
            1e-10 * b.norm());
}

}  // namespace
}  // namespace tailor::low_rank_hessian_test
