#pragma once
// Sparse symmetric factorization with CHOLMOD.
//
// The matrix is given as the upper triangle of a compressed column matrix (as assembled by
// ReducedAssembler). analyze() computes the fill-reducing ordering and symbolic factor once
// per sparsity pattern; factorize() reuses it for new values. A supernodal Cholesky LL^T is
// tried first; when the matrix is not positive definite, a simplicial LDL^T of the same
// matrix is computed instead (no pivoting: it succeeds for indefinite matrices with nonzero
// leading minors), and the number of negative pivots is reported.
#include <memory>
#include <string>

#include "forward/core/types.hpp"

namespace tailor {

struct FactorizationResult {
  bool success = false;           // a usable factor exists (LL^T or LDL^T)
  bool positive_definite = false; // LL^T succeeded
  int negative_pivots = 0;        // of LDL^T (0 when positive definite)
  std::string message;            // why not, when !success or when LDL^T was needed
};

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
  // Solves A x = b with the last successful factorization; throws std::logic_error otherwise.
  Vector solve(const Vector& b) const;
  Matrix solve_columns(const Matrix& b) const;  // several right-hand sides

  bool has_factor() const;
  bool is_ldlt() const;
  int rows() const { return rows_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int rows_ = 0;
};

}  // namespace tailor
