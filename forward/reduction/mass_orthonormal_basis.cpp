#include "forward/reduction/mass_orthonormal_basis.hpp"

#include <cmath>
#include <stdexcept>

namespace tailor {

Matrix mass_orthonormal_basis(const Matrix& vectors, const SparseMatrix& mass, double drop_tolerance,
                              std::vector<int>* kept) {
  if (mass.rows() != vectors.rows() || mass.cols() != vectors.rows())
    throw std::invalid_argument("mass_orthonormal_basis: " + std::to_string(vectors.rows()) +
                                "-row vectors and a " + std::to_string(mass.rows()) + " x " +
                                std::to_string(mass.cols()) + " mass matrix");
  if (!(drop_tolerance > 0.0 && drop_tolerance < 1.0))
    throw std::invalid_argument("mass_orthonormal_basis: drop_tolerance must be in (0, 1)");
  Matrix basis(vectors.rows(), vectors.cols());
  Matrix mass_basis(vectors.rows(), vectors.cols());  // M times each kept column
  Eigen::Index k = 0;
  if (kept) kept->clear();
  for (Eigen::Index c = 0; c < vectors.cols(); ++c) {
    Vector v = vectors.col(c);
    const double before = std::sqrt(std::max(v.dot(mass * v), 0.0));
    if (!(before > 0.0)) continue;
    for (int pass = 0; pass < 2; ++pass)
      for (Eigen::Index j = 0; j < k; ++j) v -= mass_basis.col(j).dot(v) * basis.col(j);
    const Vector mv = mass * v;
    const double after = std::sqrt(std::max(v.dot(mv), 0.0));
    if (!(after > drop_tolerance * before)) continue;
    basis.col(k) = v / after;
    mass_basis.col(k) = mv / after;
    if (kept) kept->push_back(static_cast<int>(c));
    ++k;
  }
  return basis.leftCols(k);
}

}  // namespace tailor
