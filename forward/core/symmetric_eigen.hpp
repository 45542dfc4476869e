#pragma once
// Eigen-decomposition of a small dense symmetric matrix, compiled once for every size
// (forward/core/symmetric_eigen.cpp, Eigen's SelfAdjointEigenSolver on a run-time size). Each
// fixed-size instantiation of Eigen's solver costs seconds of compile time in every translation
// unit that names it. The run-time size costs, per call with eigenvectors, 0.16 us against
// 0.13 us at 2x2, 0.61 against 0.41 us at 3x3, 1.08 against 0.92 us at 4x4, 5.1 against 4.7 us at
// 9x9 and the same at 12x12 (docs/testing.md, "Build time"). Used by the PSD projection, the
// torus distances' Newton loops, the isotropic tangent projection and the tests' references.
#include <Eigen/Core>

namespace tailor {

namespace symmetric_eigen_detail {
// The column-major n x n symmetric matrix at `a`; eigenvalues ascending into `values` (n), unit
// eigenvectors as the columns of `vectors` (n x n, column-major) unless it is null.
void decompose(const double* a, int n, double* values, double* vectors);
}  // namespace symmetric_eigen_detail

// A = vectors diag(values) vectors^T, values ascending.
template <int N>
void symmetric_eigen(const Eigen::Matrix<double, N, N>& A, Eigen::Matrix<double, N, 1>& values,
                     Eigen::Matrix<double, N, N>& vectors) {
  const int n = static_cast<int>(A.rows());
  values.resize(n);
  vectors.resize(n, n);
  symmetric_eigen_detail::decompose(A.data(), n, values.data(), vectors.data());
}

// The eigenvalues of a symmetric matrix, ascending.
Eigen::VectorXd symmetric_eigenvalues(const Eigen::MatrixXd& A);

}  // namespace tailor
