#include "forward/solve/fixed_preconditioner_cg.hpp"

#include <stdexcept>
#include <string>

#include "forward/solve/preconditioned_cg.hpp"

namespace tailor {

FixedPreconditionerCg::FixedPreconditionerCg(const SparseMatrix& preconditioner_upper, FixedPreconditionerOptions options)
    : options_(options) {
  if (preconditioner_upper.rows() != preconditioner_upper.cols() || preconditioner_upper.rows() == 0)
    throw std::invalid_argument("FixedPreconditionerCg: the preconditioner must be a non-empty square matrix");
  if (!(options_.relative_tolerance > 0.0 && options_.relative_tolerance < 1.0) || options_.max_iterations < 1)
    throw std::invalid_argument("FixedPreconditionerCg: relative_tolerance must lie in (0, 1), max_iterations >= 1");
  const FactorizationResult f = factor_.factorize(preconditioner_upper);
  if (!f.success || !f.positive_definite)
    throw std::runtime_error("FixedPreconditionerCg: the preconditioner is not positive definite (" + f.message + ")");
}

bool FixedPreconditionerCg::setup(const SparseMatrix& upper, std::string& message) {
  if (upper.rows() != factor_.rows() || upper.cols() != factor_.rows()) {
    message = "the Hessian has " + std::to_string(upper.rows()) + " rows, the preconditioner " +
              std::to_string(factor_.rows());
    return false;
  }
  hessian_ = upper;
  return true;
}

LinearSolveStats FixedPreconditionerCg::solve(const Vector& b, double relative_tolerance, Vector& x) {
  LinearSolveStats stats;
  stats.relative_tolerance = relative_tolerance > 0.0 ? relative_tolerance : options_.relative_tolerance;
  if (hessian_.rows() != b.size()) {
    stats.message = "solve() before setup() or with a right-hand side of the wrong size";
    last_ = stats;
    return stats;
  }
  const PcgResult r = preconditioned_cg(hessian_, factor_, b, stats.relative_tolerance, options_.max_iterations, x);
  stats.converged = r.converged;
  stats.iterations = r.iterations;
  stats.relative_residual = r.relative_residual;
  if (!r.converged)
    stats.message = "CG stopped at relative residual " + std::to_string(r.relative_residual) + " after " +
                    std::to_string(r.iterations) + " iterations (limit " + std::to_string(options_.max_iterations) +
                    ", or non-positive curvature)";
  ++solves_;
  iterations_ += r.iterations;
  recent_.push_back(r.iterations);
  if (recent_.size() > 8) recent_.erase(recent_.begin());
  last_ = stats;
  return stats;
}

LinearSolverInfo FixedPreconditionerCg::info() const {
  LinearSolverInfo i;
  i.name = name();
  i.krylov_method = "cg";
  i.preconditioner = "Cholesky factor of a fixed matrix";
  i.factorization_package = "cholmod";
  i.relative_tolerance = options_.relative_tolerance;
  i.max_iterations = options_.max_iterations;
  i.solves = solves_;
  i.iterations = iterations_;
  i.recent_iterations = recent_;
  i.last = last_;
  return i;
}

}  // namespace tailor
