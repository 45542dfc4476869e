#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <arpack/arpack.hpp>
#include <cmath>
#include <numbers>
#include <vector>

namespace tailor::arpack_test {
namespace {

// Smallest eigenpairs of tridiag(-1, 2, -1) (size n), whose eigenvalues are known in closed
// form: lambda_k = 2 - 2 cos(k pi / (n + 1)). Shift-invert about sigma = 0 (ARPACK mode 3),
// the same driver tailor uses for vibration modes: ARPACK asks for y = A^{-1} x by reverse
// communication and we answer with a factorization.
TEST(smoke, ArpackShiftInvertFindsSmallestLaplacianEigenvalues) {
  const a_int n = 60, nev = 4, ncv = 20;
  const Eigen::MatrixXd a = 2.0 * Eigen::MatrixXd::Identity(n, n) -
                            Eigen::MatrixXd::Identity(n, n + 1).rightCols(n) -
                            Eigen::MatrixXd::Identity(n + 1, n).bottomRows(n);
  const Eigen::LDLT<Eigen::MatrixXd> factorization(a);

  const double tol = 0.0;  // 0 means machine precision
  a_int ido = 0, info = 0;
  a_int iparam[11] = {}, ipntr[11] = {};
  iparam[0] = 1;    // exact shifts
  iparam[2] = 300;  // max Arnoldi restarts
  iparam[6] = 3;    // shift-invert
  const a_int lworkl = ncv * (ncv + 8);
  std::vector<double> resid(n), v(n * ncv), workd(3 * n), workl(lworkl);
  while (true) {
    arpack::saupd(ido, arpack::bmat::identity, n, arpack::which::largest_magnitude, nev, tol, resid.data(),
                  ncv, v.data(), n, iparam, ipntr, workd.data(), workl.data(), lworkl, info);
    if (ido != -1 && ido != 1) break;
    Eigen::Map<const Eigen::VectorXd> x(workd.data() + ipntr[0] - 1, n);
    Eigen::Map<Eigen::VectorXd>(workd.data() + ipntr[1] - 1, n) = factorization.solve(x);
  }
  ASSERT_EQ(info, 0);
  ASSERT_EQ(ido, 99);
  EXPECT_GE(iparam[4], nev);  // number of converged Ritz values

  std::vector<a_int> select(ncv);
  std::vector<double> eigenvalues(nev), eigenvectors(n * nev);
  arpack::seupd(1, arpack::howmny::ritz_vectors, select.data(), eigenvalues.data(), eigenvectors.data(), n,
                0.0, arpack::bmat::identity, n, arpack::which::largest_magnitude, nev, tol, resid.data(), ncv,
                v.data(), n, iparam, ipntr, workd.data(), workl.data(), lworkl, info);
  ASSERT_EQ(info, 0);

  for (int k = 1; k <= nev; ++k) {  // seupd returns them in ascending order, already un-shifted
    const double exact = 2.0 - 2.0 * std::cos(k * std::numbers::pi / (n + 1));
    EXPECT_NEAR(eigenvalues[k - 1], exact, 1e-12) << "k = " << k;
    Eigen::Map<const Eigen::VectorXd> z(eigenvectors.data() + (k - 1) * n, n);
    EXPECT_LT((a * z - eigenvalues[k - 1] * z).norm(), 1e-10) << "k = " << k;
  }
}

}  // namespace
}  // namespace tailor::arpack_test
