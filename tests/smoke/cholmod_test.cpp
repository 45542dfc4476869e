#include <cholmod.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace tailor::cholmod_test {
namespace {

// The 1D Laplacian tridiag(-1, 2, -1) of size n with right-hand side 1 has the exact
// solution x_i = i (n + 1 - i) / 2 (i = 1..n): the discrete parabola.
TEST(smoke, CholmodSupernodalSolveOfLaplacian) {
  int version[3] = {0, 0, 0};
  cholmod_version(version);
  std::printf("CHOLMOD %d.%d.%d\n", version[0], version[1], version[2]);
  // Headers and library agree (a mismatch means two SuiteSparse installs are mixed).
  EXPECT_EQ(version[0], CHOLMOD_MAIN_VERSION);
  EXPECT_EQ(version[1], CHOLMOD_SUB_VERSION);

  cholmod_common common;
  cholmod_start(&common);
  // Force the supernodal path so the dense kernels (dsyrk/dgemm/dpotrf) run through BLAS.
  common.supernodal = CHOLMOD_SUPERNODAL;

  const int n = 200;
  cholmod_triplet* triplets = cholmod_allocate_triplet(n, n, 2 * n - 1, -1, CHOLMOD_REAL, &common);
  auto add = [triplets](int row, int col, double value) {
    static_cast<int*>(triplets->i)[triplets->nnz] = row;
    static_cast<int*>(triplets->j)[triplets->nnz] = col;
    static_cast<double*>(triplets->x)[triplets->nnz] = value;
    ++triplets->nnz;
  };
  for (int i = 0; i < n; ++i) {  // lower triangle only (stype -1)
    add(i, i, 2.0);
    if (i + 1 < n) add(i + 1, i, -1.0);
  }
  cholmod_sparse* a = cholmod_triplet_to_sparse(triplets, 0, &common);
  cholmod_dense* b = cholmod_ones(n, 1, CHOLMOD_REAL, &common);

  cholmod_factor* factor = cholmod_analyze(a, &common);
  cholmod_factorize(a, factor, &common);
  EXPECT_EQ(common.status, CHOLMOD_OK);
  EXPECT_TRUE(factor->is_super);
  cholmod_dense* x = cholmod_solve(CHOLMOD_A, factor, b, &common);
  ASSERT_NE(x, nullptr);

  const auto* solution = static_cast<const double*>(x->x);
  double max_error = 0.0;
  for (int i = 1; i <= n; ++i) {
    const double exact = 0.5 * i * (n + 1 - i);
    max_error = std::max(max_error, std::abs(solution[i - 1] - exact) / exact);
  }
  EXPECT_LT(max_error, 1e-10);

  cholmod_free_dense(&x, &common);
  cholmod_free_factor(&factor, &common);
  cholmod_free_dense(&b, &common);
  cholmod_free_sparse(&a, &common);
  cholmod_free_triplet(&triplets, &common);
  cholmod_finish(&common);
}

}  // namespace
}  // namespace tailor::cholmod_test
