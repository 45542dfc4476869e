#include "forward/dynamics/damping_examples.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "forward/reduction/generalized_eigen.hpp"
#include "forward/solve/sparse_cholesky.hpp"

namespace tailor {

Matrix mass_orthonormalize(const Matrix& examples, const SparseMatrix& mass, double tolerance) {
  if (mass.rows() != examples.rows() || mass.cols() != examples.rows())
    throw std::invalid_argument("mass_orthonormalize: examples have " + std::to_string(examples.rows()) +
                                " rows, the mass matrix is " + std::to_string(mass.rows()) + " x " +
                                std::to_string(mass.cols()));
  Matrix U = examples;
  for (Eigen::Index j = 0; j < U.cols(); ++j) {
    if (!U.col(j).allFinite())
      throw std::invalid_argument("damping example " + std::to_string(j) + " has non-finite entries");
    const double norm0 = std::sqrt(std::max(0.0, U.col(j).dot(mass * U.col(j))));
    if (!(norm0 > 0.0))
      throw std::invalid_argument("damping example " + std::to_string(j) + " is zero (or massless)");
    // Two passes of modified Gram-Schmidt: one pass loses orthogonality for near-dependent input.
    for (int pass = 0; pass < 2; ++pass)
      for (Eigen::Index i = 0; i < j; ++i) U.col(j) -= U.col(i).dot(mass * U.col(j)) * U.col(i);
    const double norm = std::sqrt(std::max(0.0, U.col(j).dot(mass * U.col(j))));
    if (!(norm > tolerance * norm0))
      throw std::invalid_argument(
          "damping example " + std::to_string(j) +
          " is linearly dependent on the examples before it (its M-orthogonal remainder is " +
          std::to_string(norm / norm0) + " of its M-norm)");
    U.col(j) /= norm;
  }
  return U;
}

Matrix eigenmode_examples(const SparseMatrix& stiffness, const SparseMatrix& mass, const SparseMatrix& basis,
                          const std::vector<int>& indices, Vector* eigenvalues) {
  if (indices.empty()) return Matrix(stiffness.rows(), 0);
  const int count = *std::max_element(indices.begin(), indices.end()) + 1;
  if (*std::min_element(indices.begin(), indices.end()) < 0)
    throw std::invalid_argument("eigenmode_examples: mode indices must be >= 0");
  const SparseMatrix K = basis.transpose() * stiffness * basis, M = basis.transpose() * mass * basis;
  const GeneralizedEigenResult eig = generalized_eigenpairs(K, M, count);
  if (!eig.success) throw std::runtime_error("eigenmode_examples: " + eig.message);
  Matrix U(stiffness.rows(), static_cast<Eigen::Index>(indices.size()));
  if (eigenvalues) eigenvalues->resize(static_cast<Eigen::Index>(indices.size()));
  for (std::size_t k = 0; k < indices.size(); ++k) {
    U.col(static_cast<Eigen::Index>(k)) = basis * eig.eigenvectors.col(indices[k]);
    if (eigenvalues) (*eigenvalues)[static_cast<Eigen::Index>(k)] = eig.eigenvalues[indices[k]];
  }
  return U;
}

Matrix static_response_examples(const SparseMatrix& stiffness, const SparseMatrix& basis,
                                const Matrix& loads) {
  if (loads.rows() != stiffness.rows())
    throw std::invalid_argument("static_response_examples: loads have " + std::to_string(loads.rows()) +
                                " rows, the model " + std::to_string(stiffness.rows()) + " DOFs");
  const SparseMatrix K = basis.transpose() * stiffness * basis;
  SparseMatrix upper = K.triangularView<Eigen::Upper>();
  upper.makeCompressed();
  SparseCholesky factor;
  const FactorizationResult f = factor.factorize(upper);
  if (!f.success || !f.positive_definite)
    throw std::runtime_error(
        "static_response_examples: the constrained stiffness is singular (is the body fixed?)");
  return basis * factor.solve_columns(Matrix(basis.transpose() * loads));
}

}  // namespace tailor
