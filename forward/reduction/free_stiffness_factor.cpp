#include "forward/reduction/free_stiffness_factor.hpp"

#include <stdexcept>

#include "forward/reduction/free_space.hpp"
#include "forward/solve/sparse_cholesky.hpp"

namespace tailor {

FreeStiffnessFactor::FreeStiffnessFactor(const Model& model, const Vector& x, const Vector& p)
    : model_(model), factor_(std::make_unique<SparseCholesky>()) {
  SparseMatrix upper = SparseMatrix(free_stiffness(model, x, p).triangularView<Eigen::Upper>());
  upper.makeCompressed();
  const FactorizationResult f = factor_->factorize(upper);
  if (!f.success || !f.positive_definite)
    throw std::runtime_error(
        "the stiffness in the free unknowns is not positive definite (is the body constrained?): " + f.message);
}

FreeStiffnessFactor::~FreeStiffnessFactor() = default;

Matrix FreeStiffnessFactor::solve(const Matrix& rhs) const {
  const Elimination& e = model_.elimination();
  return e.basis() * factor_->solve_columns(Matrix(e.basis().transpose() * rhs));
}

}  // namespace tailor
