#include "forward/reduction/generalized_eigen.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <arpack/arpack.hpp>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "forward/core/symmetric_eigen.hpp"
#include "forward/solve/sparse_cholesky.hpp"

namespace tailor {
namespace {

// Text for an ARPACK info code of dsaupd (the iteration) or dseupd (the extraction); most
// codes mean the same in both.
std::string arpack_message(a_int info, bool extraction) {
  switch (info) {
    case -1: return "n must be positive";
    case -2: return "count (nev) must be positive";
    case -3: return "ncv must satisfy count < ncv <= n";
    case -5: return "invalid 'which' option";
    case -6: return "invalid bmat option";
    case -7: return "work array too short";
    case -8: return "error in the LAPACK tridiagonal eigenvalue calculation";
    case -10: return "invalid ARPACK mode";
    case -11: return "mode 1 is incompatible with bmat = 'G'";
    default: break;
  }
  if (extraction) {
    switch (info) {
      case 0: return "ok";
      case -9: return "error in the LAPACK eigenvector calculation";
      case -12: return "nev and which = 'BE' are incompatible";
      case -14: return "dsaupd found no eigenvalues to sufficient accuracy";
      case -15: return "howmny must be 'A' or 'S'";
      case -16: return "howmny = 'S' is not implemented";
      case -17: return "the number of converged Ritz values changed between dsaupd and dseupd";
      default: return "unknown ARPACK dseupd error";
    }
  }
  switch (info) {
    case 0: return "converged";
    case 1: return "maximum number of iterations reached before all pairs converged";
    case 3: return "no shifts could be applied during an implicit restart (try a larger ncv)";
    case -4: return "the maximum number of iterations must be positive";
    case -9: return "the starting vector is zero";
    case -12: return "invalid shift strategy (iparam[0])";
    case -13: return "nev and which = 'BE' are incompatible";
    case -9999: return "could not build a Lanczos factorization (B may not be positive definite)";
    default: return "unknown ARPACK dsaupd error";
  }
}

// Sign each column so that its entry of largest magnitude is positive.
void normalize_signs(Matrix& x) {
  for (Eigen::Index j = 0; j < x.cols(); ++j) {
    Eigen::Index i = 0;
    x.col(j).cwiseAbs().maxCoeff(&i);
    if (x(i, j) < 0) x.col(j) *= -1.0;
  }
}

GeneralizedEigenResult dense_solve(const SparseMatrix& A, const SparseMatrix& B, int count, const Matrix& deflation,
                                   const std::string& why) {
  GeneralizedEigenResult result;
  result.dense = true;
  const Matrix a = Matrix(A), b = Matrix(B);
  // Symmetrize: the solvers read one triangle only; averaging makes both count.
  const Matrix as = 0.5 * (a + a.transpose()), bs = 0.5 * (b + b.transpose());
  Vector values;
  Matrix vectors;
  if (!generalized_symmetric_eigen(as, bs, values, vectors)) {
    result.message = "dense generalized eigensolver failed (" + why + "; B may not be positive definite)";
    return result;
  }
  // Keep the lowest `count` pairs outside span(deflation): drop the k most inside it.
  const Eigen::Index k = deflation.cols();
  std::vector<Eigen::Index> keep;
  if (k > 0) {
    const Vector inside = (deflation.transpose() * (bs * vectors)).colwise().squaredNorm();
    std::vector<Eigen::Index> order(static_cast<std::size_t>(inside.size()));
    for (Eigen::Index i = 0; i < inside.size(); ++i) order[static_cast<std::size_t>(i)] = i;
    std::stable_sort(order.begin(), order.end(), [&](Eigen::Index i, Eigen::Index j) { return inside[i] > inside[j]; });
    std::vector<bool> dropped(static_cast<std::size_t>(inside.size()), false);
    for (Eigen::Index i = 0; i < k; ++i) dropped[static_cast<std::size_t>(order[static_cast<std::size_t>(i)])] = true;
    for (Eigen::Index i = 0; i < inside.size() && static_cast<int>(keep.size()) < count; ++i)
      if (!dropped[static_cast<std::size_t>(i)]) keep.push_back(i);
  } else {
    for (Eigen::Index i = 0; i < count; ++i) keep.push_back(i);
  }
  result.eigenvalues = values(keep);  // ascending
  result.eigenvectors = vectors(Eigen::all, keep);
  normalize_signs(result.eigenvectors);
  result.converged = count;
  result.success = true;
  result.message = "solved densely (" + why + ")";
  return result;
}

}  // namespace

GeneralizedEigenResult generalized_eigenpairs(const SparseMatrix& A, const SparseMatrix& B, int count,
                                              const GeneralizedEigenOptions& options) {
  if (A.rows() != A.cols() || B.rows() != B.cols())
    throw std::invalid_argument("generalized_eigenpairs: A and B must be square");
  if (A.rows() != B.rows())
    throw std::invalid_argument("generalized_eigenpairs: A is " + std::to_string(A.rows()) + " x " +
                                std::to_string(A.cols()) + " but B is " + std::to_string(B.rows()) + " x " +
                                std::to_string(B.cols()));
  const int n = static_cast<int>(A.rows());
  if (count < 1 || count > n - 1)
    throw std::invalid_argument("generalized_eigenpairs: count = " + std::to_string(count) +
                                " is not in [1, n - 1] = [1, " + std::to_string(n - 1) + "]");
  if (!(options.tolerance >= 0.0))
    throw std::invalid_argument("generalized_eigenpairs: tolerance must be >= 0");
  if (options.max_iterations < 1)
    throw std::invalid_argument("generalized_eigenpairs: max_iterations must be >= 1");
  if (options.ncv != 0 && (options.ncv <= count || options.ncv > n))
    throw std::invalid_argument("generalized_eigenpairs: ncv = " + std::to_string(options.ncv) +
                                " must satisfy count < ncv <= n (or be 0 for the default)");
  if (options.shift && !std::isfinite(*options.shift))
    throw std::invalid_argument("generalized_eigenpairs: shift must be finite");

  const Matrix& deflation = options.deflation;
  if (deflation.size() > 0 && (deflation.rows() != n || count + deflation.cols() > n - 1))
    throw std::invalid_argument("generalized_eigenpairs: the deflation basis must have n rows and count + its columns <= n - 1");
  if (n <= options.dense_threshold)
    return dense_solve(A, B, count, deflation, "n = " + std::to_string(n) + " is small");
  if (count + deflation.cols() >= n - 1) return dense_solve(A, B, count, deflation, "count >= n - 1, beyond ARPACK");
  const Matrix b_deflation = deflation.size() > 0 ? Matrix(B * deflation) : Matrix();
  // y <- (I - R R^T B) y: keeps the Lanczos vectors B-orthogonal to the deflated subspace.
  const auto deflate = [&](Eigen::Map<Vector>& y) {
    if (deflation.size() > 0) y -= deflation * (b_deflation.transpose() * y);
  };

  // Shift: small negative by default, scaled to the ratio of the two matrices' diagonals.
  double sigma = 0.0;
  if (options.shift) {
    sigma = *options.shift;
  } else {
    const double max_a = A.diagonal().maxCoeff(), max_b = B.diagonal().maxCoeff();
    const double scale = (max_a > 0 && max_b > 0 && std::isfinite(max_a / max_b)) ? max_a / max_b : 1.0;
    sigma = -1e-8 * scale;
  }

  GeneralizedEigenResult result;
  result.shift = sigma;
  SparseMatrix shifted = A - sigma * B;
  SparseMatrix upper = shifted.triangularView<Eigen::Upper>();
  upper.makeCompressed();
  SparseCholesky factor;
  const FactorizationResult fact = factor.factorize(upper);
  if (!fact.success) {
    result.message = "factorization of A - sigma B failed: " + fact.message;
    return result;
  }

  const a_int nev = count;
  const a_int ncv = options.ncv != 0 ? options.ncv : std::min(n, std::max(2 * count + 1, 20));
  const a_int lworkl = ncv * (ncv + 8);
  std::vector<double> resid(static_cast<std::size_t>(n)), v(static_cast<std::size_t>(n) * ncv),
      workd(3 * static_cast<std::size_t>(n)), workl(static_cast<std::size_t>(lworkl));
  a_int iparam[11] = {}, ipntr[11] = {};
  iparam[0] = 1;                       // exact shifts
  iparam[2] = options.max_iterations;  // max restarts
  iparam[6] = 3;                       // shift-invert: OP = (A - sigma B)^{-1} B, inner product B
  // A fixed start vector (info = 1): ARPACK's own random start continues from call to call in
  // one process, so a repeated eigenvalue's eigenvectors (symmetric meshes have many) would come
  // out in another basis every call, and the same scene would give another design space.
  std::mt19937_64 rng(20151);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (double& r : resid) r = uniform(rng);
  a_int ido = 0, info = 1;
  const double tol = options.tolerance;
  int applications = 0;

  while (true) {
    arpack::saupd(ido, arpack::bmat::generalized, n, arpack::which::largest_magnitude, nev, tol, resid.data(),
                  ncv, v.data(), n, iparam, ipntr, workd.data(), workl.data(), lworkl, info);
    if (ido != -1 && ido != 1 && ido != 2) break;
    const Eigen::Map<const Vector> x(workd.data() + ipntr[0] - 1, n);
    Eigen::Map<Vector> y(workd.data() + ipntr[1] - 1, n);
    if (ido == -1) {  // y = OP x, B x not yet known
      y = factor.solve(B * Vector(x));
      deflate(y);
      ++applications;
    } else if (ido == 1) {  // y = OP x with B x given at ipntr[2]
      const Eigen::Map<const Vector> bx(workd.data() + ipntr[2] - 1, n);
      y = factor.solve(Vector(bx));
      deflate(y);
      ++applications;
    } else {  // ido == 2: y = B x
      y = B * Vector(x);
    }
  }
  result.iterations = static_cast<int>(iparam[2]);
  result.operator_applications = applications;
  if (info != 0 && info != 1) {
    result.message = "ARPACK dsaupd error " + std::to_string(info) + ": " + arpack_message(info, false);
    return result;
  }
  const std::string saupd_status = arpack_message(info, false);
  const int nconv = static_cast<int>(iparam[4]);
  if (nconv < 1) {
    result.message = "ARPACK dsaupd: no pair converged (" + saupd_status + ")";
    return result;
  }

  std::vector<a_int> select(static_cast<std::size_t>(ncv));
  std::vector<double> d(static_cast<std::size_t>(nev)), z(static_cast<std::size_t>(n) * nev);
  a_int einfo = 0;
  arpack::seupd(1, arpack::howmny::ritz_vectors, select.data(), d.data(), z.data(), n, sigma,
                arpack::bmat::generalized, n, arpack::which::largest_magnitude, nev, tol, resid.data(), ncv,
                v.data(), n, iparam, ipntr, workd.data(), workl.data(), lworkl, einfo);
  if (einfo != 0) {
    result.message = "ARPACK dseupd error " + std::to_string(einfo) + ": " + arpack_message(einfo, true);
    return result;
  }
  const int got = std::min(nconv, count);
  // dseupd returns the converged values (un-shifted) in ascending order; sort to be sure.
  std::vector<int> order(static_cast<std::size_t>(got));
  for (int i = 0; i < got; ++i) order[static_cast<std::size_t>(i)] = i;
  std::sort(order.begin(), order.end(),
            [&](int i, int j) { return d[static_cast<std::size_t>(i)] < d[static_cast<std::size_t>(j)]; });
  Eigen::Map<const Matrix> zmap(z.data(), n, nev);
  result.eigenvalues.resize(got);
  result.eigenvectors.resize(n, got);
  for (int k = 0; k < got; ++k) {
    const int i = order[static_cast<std::size_t>(k)];
    result.eigenvalues[k] = d[static_cast<std::size_t>(i)];
    result.eigenvectors.col(k) = zmap.col(i);
  }
  normalize_signs(result.eigenvectors);
  result.converged = got;
  result.success = got == count;
  result.message = result.success ? "ARPACK shift-invert: " + std::to_string(got) + " pairs converged"
                                  : "ARPACK shift-invert: only " + std::to_string(got) + " of " +
                                        std::to_string(count) + " pairs converged (" + saupd_status + ")";
  if (fact.positive_definite == false) result.message += "; A - sigma B needed LDL^T: " + fact.message;
  return result;
}

}  // namespace tailor
