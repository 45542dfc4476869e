#include "forward/reduction/constrained_modes.hpp"

#include <Eigen/QR>
#include <stdexcept>

namespace tailor {

SparseMatrix constraint_null_space(const Matrix& constraints, double tolerance, int* rank_out) {
  const int n = static_cast<int>(constraints.cols());
  Triplets t;
  if (constraints.rows() == 0) {
    for (int i = 0; i < n; ++i) t.emplace_back(i, i, 1.0);
    SparseMatrix identity(n, n);
    identity.setFromTriplets(t.begin(), t.end());
    if (rank_out) *rank_out = 0;
    return identity;
  }
  Eigen::ColPivHouseholderQR<Matrix> qr(constraints);
  qr.setThreshold(tolerance);
  const int rank = static_cast<int>(qr.rank());
  const Matrix r = qr.matrixR().topRows(rank).template triangularView<Eigen::Upper>();
  const Matrix r1 = r.leftCols(rank).template triangularView<Eigen::Upper>();
  const Matrix coupling = -r1.template triangularView<Eigen::Upper>().solve(r.rightCols(n - rank));
  const Eigen::VectorXi perm = qr.colsPermutation().indices();
  for (int j = 0; j < n - rank; ++j) {
    t.emplace_back(perm[rank + j], j, 1.0);
    if (coupling.col(j).cwiseAbs().maxCoeff() == 0.0) continue;  // an unconstrained DOF
    for (int i = 0; i < rank; ++i)
      if (coupling(i, j) != 0.0) t.emplace_back(perm[i], j, coupling(i, j));
  }
  SparseMatrix basis(n, n - rank);
  basis.setFromTriplets(t.begin(), t.end());
  if (rank_out) *rank_out = rank;
  return basis;
}

ConstrainedModes constrained_modes(const SparseMatrix& stiffness, const SparseMatrix& mass, const Matrix& constraints,
                                   int count, const GeneralizedEigenOptions& options) {
  const int n = static_cast<int>(stiffness.rows());
  if (stiffness.cols() != n || mass.rows() != n || mass.cols() != n || constraints.cols() != n)
    throw std::invalid_argument("constrained modes: K, M (n x n) and C (m x n) sizes differ");
  ConstrainedModes out;
  const SparseMatrix basis = constraint_null_space(constraints, 1e-10, &out.constraint_rank);
  if (count < 1 || count >= basis.cols())
    throw std::invalid_argument("constrained modes: count must be in [1, n - rank C - 1]");
  const SparseMatrix a = SparseMatrix(basis.transpose() * stiffness * basis);
  const SparseMatrix b = SparseMatrix(basis.transpose() * mass * basis);
  out.solve = generalized_eigenpairs(a, b, count, options);
  if (!out.solve.success) throw std::runtime_error("constrained modes: " + out.solve.message);
  out.eigenvalues = out.solve.eigenvalues;
  out.modes = basis * out.solve.eigenvectors;
  out.solve.eigenvectors.resize(0, 0);
  return out;
}

}  // namespace tailor
