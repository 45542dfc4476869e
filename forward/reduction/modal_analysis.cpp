#include "forward/reduction/modal_analysis.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "forward/reduction/free_space.hpp"

namespace tailor {

Vector frequencies_hz(const Vector& eigenvalues) {
  return eigenvalues.unaryExpr(
      [](double l) { return std::sqrt(std::max(l, 0.0)) / (2.0 * std::numbers::pi); });
}

ModalAnalysis modal_analysis(const Model& model, int dim, const Vector& x, const Vector& p,
                             const SparseMatrix& mass, const ModalAnalysisOptions& options) {
  if (x.size() != model.num_dofs())
    throw std::invalid_argument("modal_analysis: the state has " + std::to_string(x.size()) +
                                " entries, the model " + std::to_string(model.num_dofs()) + " DOFs");
  if (dim != 2 && dim != 3) throw std::invalid_argument("modal_analysis: dim must be 2 or 3");
  const SparseMatrix K = free_stiffness(model, x, p);
  const SparseMatrix M = free_mass(model, mass);
  const int n = static_cast<int>(K.rows());
  if (options.count < 1 || options.count > n - 1)
    throw std::invalid_argument("modal_analysis: count = " + std::to_string(options.count) +
                                " is not in [1, " + std::to_string(n - 1) + "]");

  ModalAnalysis out;
  Matrix rigid = admissible_rigid_modes(model, x, dim, M);
  const double scale = K.diagonal().cwiseAbs().maxCoeff();
  for (Eigen::Index k = 0; k < rigid.cols(); ++k) {
    const double residual = (K * rigid.col(k)).norm();
    if (residual > options.rigid_tolerance * scale * rigid.col(k).norm())
      throw std::runtime_error("modal_analysis: rigid motion " + std::to_string(k) +
                               " is not a null mode of the stiffness (relative residual " +
                               std::to_string(residual / (scale * rigid.col(k).norm())) +
                               "); is the state pre-stressed?");
  }
  const int k = static_cast<int>(rigid.cols());
  if (options.count + k > n - 1)
    throw std::invalid_argument("modal_analysis: count + rigid modes exceeds n - 1");

  GeneralizedEigenOptions eigen = options.eigen;
  Matrix elastic;
  if (options.rigid == RigidModeHandling::deflate || k == 0) {
    eigen.deflation = rigid;
    out.solve = generalized_eigenpairs(K, M, options.count, eigen);
    if (!out.solve.success) throw std::runtime_error("modal_analysis: " + out.solve.message);
    elastic = std::move(out.solve.eigenvectors);
    out.eigenvalues = out.solve.eigenvalues;
    out.rigid_eigenvalues = (rigid.transpose() * (K * rigid)).diagonal();
  } else {
    eigen.deflation.resize(0, 0);
    out.solve = generalized_eigenpairs(K, M, options.count + k, eigen);
    if (!out.solve.success) throw std::runtime_error("modal_analysis: " + out.solve.message);
    const Matrix& all = out.solve.eigenvectors;
    const Vector inside = (rigid.transpose() * (M * all)).colwise().squaredNorm();
    std::vector<Eigen::Index> rigid_columns, elastic_columns;
    for (Eigen::Index j = 0; j < all.cols(); ++j)
      (inside[j] > 0.5 ? rigid_columns : elastic_columns).push_back(j);
    if (static_cast<int>(rigid_columns.size()) != k)
      throw std::runtime_error("modal_analysis: " + std::to_string(rigid_columns.size()) +
                               " computed modes lie in the rigid subspace, expected " + std::to_string(k));
    elastic = all(Eigen::all, elastic_columns);
    out.eigenvalues = out.solve.eigenvalues(elastic_columns);
    out.rigid_eigenvalues = out.solve.eigenvalues(rigid_columns);
    rigid = all(Eigen::all, rigid_columns);  // the computed ones, M-orthonormal
    out.solve.eigenvectors.resize(0, 0);
  }
  out.frequencies = frequencies_hz(out.eigenvalues);
  const SparseMatrix& s = model.elimination().basis();
  out.modes = s * elastic;
  out.rigid_modes = s * rigid;
  out.free_modes = std::move(elastic);
  return out;
}

}  // namespace tailor
