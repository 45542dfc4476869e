#include "forward/core/symmetric_eigen.hpp"

#include <Eigen/Eigenvalues>

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

}  // namespace tailor
