#include "forward/reduction/modal_derivatives.hpp"

#include <algorithm>
#include <stdexcept>

#include "forward/reduction/free_space.hpp"
#include "forward/solve/sparse_cholesky.hpp"

namespace tailor {
namespace {

// The free-space stiffness K_y at x, factorized.
class FreeStiffnessSolver {
 public:
  FreeStiffnessSolver(const Model& model, const Vector& x, const Vector& p) : model_(model) {
    SparseMatrix upper = SparseMatrix(free_stiffness(model, x, p).triangularView<Eigen::Upper>());
    upper.makeCompressed();
    const FactorizationResult f = factor_.factorize(upper);
    if (!f.success || !f.positive_definite)
      throw std::runtime_error(
          "the stiffness in the free unknowns is not positive definite (is the body constrained?): " +
          f.message);
  }
  // S K_y^{-1} S^T rhs for full-space right-hand sides (columns).
  Matrix solve(const Matrix& rhs) const {
    const Elimination& e = model_.elimination();
    return e.basis() * factor_.solve_columns(Matrix(e.basis().transpose() * rhs));
  }

 private:
  const Model& model_;
  SparseCholesky factor_;
};

void check_sizes(const Model& model, const Vector& x, const Matrix& vectors, const char* what) {
  if (x.size() != model.num_dofs() || vectors.rows() != model.num_dofs())
    throw std::invalid_argument(std::string(what) + ": state and vectors need " +
                                std::to_string(model.num_dofs()) + " rows");
}

}  // namespace

int modal_derivative_index(int i, int j, int r) {
  if (i > j) std::swap(i, j);
  return i * r - i * (i - 1) / 2 + (j - i);
}

Vector stiffness_directional_derivative(const Model& model, const Vector& x, const Vector& p, const Vector& a,
                                        const Vector& b, double step) {
  const double amax = a.cwiseAbs().maxCoeff();
  if (!(step > 0.0) || !(amax > 0.0))
    throw std::invalid_argument("stiffness_directional_derivative: need step > 0 and a nonzero direction");
  const double e = step / amax;
  const Vector plus = model.hessian_times(x + e * a, p, b), minus = model.hessian_times(x - e * a, p, b);
  return (plus - minus) / (2.0 * e);
}

Matrix modal_derivatives(const Model& model, const Vector& x, const Vector& p, const Matrix& modes,
                         const ModalDerivativeOptions& options) {
  check_sizes(model, x, modes, "modal_derivatives");
  const int r = static_cast<int>(modes.cols());
  double step = options.step;
  if (step == 0.0) step = 1e-3 * std::max(x.maxCoeff() - x.minCoeff(), 1e-300);
  if (!(step > 0.0))
    throw std::invalid_argument("modal_derivatives: step must be > 0 (or 0 for the default)");
  const FreeStiffnessSolver stiffness(model, x, p);
  Matrix rhs(model.num_dofs(), r * (r + 1) / 2);
  for (int i = 0; i < r; ++i)
    for (int j = i; j < r; ++j)
      rhs.col(modal_derivative_index(i, j, r)) =
          -stiffness_directional_derivative(model, x, p, modes.col(i), modes.col(j), step);
  return stiffness.solve(rhs);
}

Matrix krylov_blocks(const Model& model, const Vector& x, const Vector& p, const SparseMatrix& mass,
                     const Matrix& start, int levels) {
  check_sizes(model, x, start, "krylov_blocks");
  if (levels < 0) throw std::invalid_argument("krylov_blocks: levels must be >= 0");
  const FreeStiffnessSolver stiffness(model, x, p);
  Matrix out(start.rows(), start.cols() * levels);
  Matrix block = start;
  for (int l = 0; l < levels; ++l) {
    block = stiffness.solve(mass * block);
    for (Eigen::Index c = 0; c < block.cols(); ++c) {
      const double norm = std::sqrt(std::max(block.col(c).dot(mass * block.col(c)), 0.0));
      if (norm > 0.0) block.col(c) /= norm;
    }
    out.middleCols(l * start.cols(), start.cols()) = block;
  }
  return out;
}

}  // namespace tailor
