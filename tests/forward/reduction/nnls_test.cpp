// Lawson-Hanson NNLS (forward/reduction/nnls.hpp) against solutions known in closed form.
#include "forward/core/symmetric_eigen.hpp"
#include "forward/reduction/nnls.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

namespace tailor::nnls_test {
namespace {

// Reference: with A = I the problem separates, min (x_i - b_i)^2 with x_i >= 0: x = max(b, 0).
TEST(Nnls, IdentityIsTheClampedRightHandSide) {
  Vector b(6);
  b << 1.5, -2.0, 0.0, 3.0, -0.1, 0.7;
  const NnlsResult r = nnls(Matrix::Identity(6, 6), b);
  EXPECT_TRUE(r.converged);
  EXPECT_LT((r.x - b.cwiseMax(0.0)).norm(), 1e-14);
  EXPECT_NEAR(r.residual, std::sqrt(2.0 * 2.0 + 0.1 * 0.1), 1e-14);
}

// Reference: the Karush-Kuhn-Tucker point built by hand. Columns 0 and 2 active with x* =
// (2, 0, 0.5, 0); the residual b - A x* = t is orthogonal to those columns, and the other
// columns are chosen with A_k^T t < 0, so x* is the unique minimizer (A full column rank).
TEST(Nnls, ReachesAConstructedKktPoint) {
  std::srand(11);
  Matrix a = Matrix::Random(8, 4);
  Vector t = Vector::Random(8);
  Matrix active(8, 2);
  active << a.col(0), a.col(2);
  t -= active * pivoted_qr_solve(active, t).x.col(0);  // orthogonal to the active columns
  for (int k : {1, 3})
    if (a.col(k).dot(t) > 0.0) a.col(k) -= 2.0 * a.col(k).dot(t) / t.squaredNorm() * t;  // A_k^T t < 0
  ASSERT_LT(a.col(1).dot(t), 0.0);
  ASSERT_LT(a.col(3).dot(t), 0.0);
  Vector x_star(4);
  x_star << 2.0, 0.0, 0.5, 0.0;
  const Vector b = a * x_star + t;
  const NnlsResult r = nnls(a, b);
  EXPECT_TRUE(r.converged);
  EXPECT_LT((r.x - x_star).norm(), 1e-12) << r.x.transpose();
  EXPECT_NEAR(r.residual, t.norm(), 1e-12);
  // A warm start (a feasible point with the wrong support) reaches the same point.
  const Vector start = Vector::Constant(4, 1.0);
  const NnlsResult warm = nnls(a, b, 0, &start);
  EXPECT_LT((warm.x - x_star).norm(), 1e-12) << warm.x.transpose();
  // An exactly representable b with x >= 0 is recovered (zero residual).
  const NnlsResult exact = nnls(a, a * Vector::Constant(4, 0.3));
  EXPECT_LT((exact.x - Vector::Constant(4, 0.3)).norm(), 1e-12);
}

TEST(Nnls, BadInputIsAClearError) {
  EXPECT_THROW(nnls(Matrix::Identity(3, 3), Vector::Ones(2)), std::invalid_argument);
  const Vector negative = -Vector::Ones(3);
  EXPECT_THROW(nnls(Matrix::Identity(3, 3), Vector::Ones(3), 0, &negative), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::nnls_test
