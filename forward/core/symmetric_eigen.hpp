#pragma once
// Dense decompositions compiled once (forward/core/symmetric_eigen.cpp): the eigen-decomposition
// of a small symmetric matrix for every size (Eigen's SelfAdjointEigenSolver on a run-time size),
// the generalized symmetric-definite problem, the singular value decomposition and two QR
// factorizations. Each
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

// The dense generalized problem A x = lambda B x, A symmetric, B symmetric positive definite
// (Eigen's GeneralizedSelfAdjointEigenSolver, compiled once: an instantiation costs several
// seconds of compile time in each unit that names it). Eigenvalues ascending, eigenvectors the
// B-orthonormal columns of `vectors`. Reads the lower triangles. Returns false, leaving the
// outputs unspecified, when the solver fails (B not positive definite).
bool generalized_symmetric_eigen(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, Eigen::VectorXd& values,
                                 Eigen::MatrixXd& vectors);

// A = U diag(singular_values) V^T by one-sided Jacobi rotations (Eigen's JacobiSVD, compiled
// once), singular values descending; U is rows x rows and V cols x cols (full), or left empty
// when not asked for.
struct SingularValueDecomposition {
  Eigen::VectorXd singular_values;
  Eigen::MatrixXd U, V;
};
SingularValueDecomposition singular_value_decomposition(const Eigen::MatrixXd& A, bool compute_u, bool compute_v);

// The least-squares solution of A X = B by Householder QR with column pivoting (Eigen's
// ColPivHouseholderQR, compiled once: about 3.5 s of compile time in each unit that names it),
// and the numerical rank the pivoting found (Eigen's default threshold).
struct PivotedQrSolution {
  Eigen::MatrixXd x;  // A.cols() x B.cols()
  int rank = 0;
};
PivotedQrSolution pivoted_qr_solve(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B);

// The first `count` columns of the orthogonal factor Q of A = Q R (Householder QR, compiled once):
// an orthonormal basis of A's column space when A has full column rank and count <= A.cols().
Eigen::MatrixXd orthonormal_columns(const Eigen::MatrixXd& A, Eigen::Index count);

}  // namespace tailor
