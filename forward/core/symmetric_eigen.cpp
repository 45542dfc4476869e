#include "forward/core/symmetric_eigen.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Eigen/SVD>

namespace tailor::symmetric_eigen_detail {

void decompose(const double* a, int n, double* values, double* vectors) {
  const Eigen::Map<const Eigen::MatrixXd> A(a, n, n);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(
      A, vectors ? Eigen::ComputeEigenvectors : Eigen::EigenvaluesOnly);
  Eigen::Map<Eigen::VectorXd>(values, n) = eig.eigenvalues();
  if (vectors) Eigen::Map<Eigen::MatrixXd>(vectors, n, n) = eig.eigenvectors();
}

}  // namespace tailor::symmetric_eigen_detail

namespace tailor {

Eigen::VectorXd symmetric_eigenvalues(const Eigen::MatrixXd& A) {
  Eigen::VectorXd values(A.rows());
  symmetric_eigen_detail::decompose(A.data(), static_cast<int>(A.rows()), values.data(), nullptr);
  return values;
}

bool generalized_symmetric_eigen(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, Eigen::VectorXd& values,
                                 Eigen::MatrixXd& vectors) {
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(A, B,
                                                                          Eigen::ComputeEigenvectors | Eigen::Ax_lBx);
  if (solver.info() != Eigen::Success) return false;
  values = solver.eigenvalues();
  vectors = solver.eigenvectors();
  return true;
}

SingularValueDecomposition singular_value_decomposition(const Eigen::MatrixXd& A, bool compute_u, bool compute_v) {
  unsigned int options = 0;
  if (compute_u) options |= Eigen::ComputeFullU;
  if (compute_v) options |= Eigen::ComputeFullV;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, options);
  SingularValueDecomposition out;
  out.singular_values = svd.singularValues();
  if (compute_u) out.U = svd.matrixU();
  if (compute_v) out.V = svd.matrixV();
  return out;
}

PivotedQrSolution pivoted_qr_solve(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  return {qr.solve(B), static_cast<int>(qr.rank())};
}

Eigen::MatrixXd orthonormal_columns(const Eigen::MatrixXd& A, Eigen::Index count) {
  return Eigen::HouseholderQR<Eigen::MatrixXd>(A).householderQ() * Eigen::MatrixXd::Identity(A.rows(), count);
}

}  // namespace tailor
