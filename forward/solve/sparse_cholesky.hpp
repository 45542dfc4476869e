#pragma once
// Sparse symmetric factorization with CHOLMOD.
//
// The matrix is given as the upper triangle of a compressed column matrix (as assembled by
// ReducedAssembler). analyze() computes the fill-reducing ordering and symbolic factor once
// per sparsity pattern; factorize() reuses it for new values. A supernodal Cholesky LL^T is
// tried first; when the matrix is not positive definite, a simplicial LDL^T of the same
// matrix is computed instead (no pivoting: it succeeds for indefinite matrices with nonzero
// leading minors), and the number of negative pivots is reported.
#include <Eigen/LU>
#include <memory>
#include <string>
#include <utility>

#include "forward/core/types.hpp"

namespace tailor {

struct FactorizationResult {
  bool success = false;           // a usable factor exists (LL^T or LDL^T)
  bool positive_definite = false; // LL^T succeeded
  int negative_pivots = 0;        // of LDL^T (0 when positive definite)
  std::string message;            // why not, when !success or when LDL^T was needed
  bool kept = false;              // NewtonSolver::factorize_hessian: the kept factor of a constant Hessian
};

// Fill-reducing orderings CHOLMOD can analyse a pattern with.
enum class FillOrdering { amd, metis, nesdis };

// The nonzeros of L and the flops of a numeric factorization that CHOLMOD's symbolic analysis
// predicts for the upper triangle `upper` (square, compressed) under one ordering, supernodal;
// NaN for both when the analysis fails. For comparing orderings; SparseCholesky chooses its own.
std::pair<double, double> estimate_factor_cost(const SparseMatrix& upper, FillOrdering ordering);

class SparseCholesky {
 public:
  SparseCholesky();
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  // Symbolic analysis of the pattern (upper triangle, compressed). Also done implicitly by the
  // first factorize() and whenever the pattern's size or nonzero count changes.
  void analyze(const SparseMatrix& upper);
  FactorizationResult factorize(const SparseMatrix& upper);
  // Makes solve() invert A + F G F^T instead of A (Sherman-Morrison-Woodbury, with the last
  // factorization; k = F.cols() extra solves now, O(n k) per solve after):
  //   (A + F G F^T)^-1 = A^-1 - A^-1 F (I + G F^T A^-1 F)^-1 G F^T A^-1.
  // factorize() drops it. Throws std::logic_error without a factorization, and
  // std::runtime_error when the capacitance matrix I + G F^T A^-1 F is singular.
  void set_low_rank_update(const Matrix& F, const Matrix& G);
  bool has_low_rank_update() const { return low_rank_factors_.cols() > 0; }
  // Solves A x = b with the last successful factorization; throws std::logic_error otherwise.
  Vector solve(const Vector& b) const;
  Matrix solve_columns(const Matrix& b) const;  // several right-hand sides

  bool has_factor() const;
  bool is_ldlt() const;
  int rows() const { return rows_; }
  // From the last symbolic analysis of the LL^T factor (0 before one): CHOLMOD's flop count of
  // a numeric factorization and the nonzeros of L (a back-solve costs about 4 nnz(L) flops).
  double factorization_flops() const;
  double factor_nonzeros() const;
  // Work done so far, for reports: numeric factorizations (an LDL^T after a failed LL^T counts
  // as a second one) and right-hand sides solved with a factor (a back-solve each: a forward and
  // a backward triangular solve).
  long numeric_factorizations() const { return numeric_factorizations_; }
  long back_solves() const { return back_solves_; }

 private:
  struct Impl;
  Matrix base_solve(const Matrix& b) const;
  std::unique_ptr<Impl> impl_;
  int rows_ = 0;
  long numeric_factorizations_ = 0;
  mutable long back_solves_ = 0;
  Matrix low_rank_factors_, low_rank_core_, low_rank_solved_;  // F, G, A^-1 F
  Eigen::PartialPivLU<Matrix> capacitance_;                  // I + G F^T A^-1 F
};

}  // namespace tailor
