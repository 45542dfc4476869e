#pragma once
// The smallest eigenpairs of a sparse symmetric generalized eigenproblem
//
//   A x = lambda B x,   A symmetric positive semidefinite, B symmetric positive definite,
//
// by ARPACK's implicitly restarted Lanczos method (dsaupd / dseupd) in shift-invert mode
// (ARPACK mode 3, bmat = 'G'): Lanczos runs on OP = (A - sigma B)^{-1} B in the B inner
// product, whose largest-magnitude eigenvalues 1 / (lambda - sigma) belong to the lambda
// nearest sigma. (A - sigma B) is factorized once by SparseCholesky (CHOLMOD, upper triangle);
// every Lanczos step costs one sparse product with B and one pair of triangular solves.
//
// Shift. By default sigma = -1e-8 * max_i A_ii / max_i B_ii: a small negative shift, so that
// A - sigma B = A + |sigma| B is positive definite even when A is singular (a Laplacian, the
// stiffness of an unconstrained body), while sigma stays far below the eigenvalues of
// interest, so the wanted pairs are still the ones nearest sigma. (When A has a zero diagonal
// the scale max A_ii / max B_ii is replaced by 1.) With an explicit options.shift the pairs
// returned are the `count` nearest sigma, which are the smallest when sigma lies below the
// spectrum.
//
// Small problems (n <= options.dense_threshold, or count >= n - 1, which ARPACK cannot do)
// are solved densely with Eigen's GeneralizedSelfAdjointEigenSolver; the result says so.
//
// Deflation. options.deflation (n x k, B-orthonormal columns spanning a subspace that A and B
// leave invariant, e.g. the rigid-body modes of a free body, A R = 0) is projected out of
// every Lanczos vector (OP becomes (I - R R^T B) OP), so the pairs returned are the lowest of
// the B-orthogonal complement of R. The dense path solves the whole problem and drops the k
// pairs lying most in span(R).
//
// Eigenvectors are B-orthonormal (X^T B X = I); each is signed so that its entry of largest
// magnitude is positive (a deterministic choice, nothing more).
#include <optional>
#include <string>

#include "forward/core/types.hpp"

namespace tailor {

struct GeneralizedEigenOptions {
  std::optional<double> shift;  // sigma; default above
  double tolerance = 0.0;       // ARPACK's relative accuracy of Ritz values; 0 = machine precision
  int max_iterations = 1000;    // ARPACK restarts (iparam[2])
  int ncv = 0;                  // Lanczos vectors; 0 = min(n, max(2 * count + 1, 20))
  int dense_threshold = 64;     // n at or below this is solved densely
  Matrix deflation;             // n x k, B-orthonormal; empty = none (see above)
};

struct GeneralizedEigenResult {
  bool success = false;           // `count` pairs converged
  bool dense = false;             // solved by the dense fallback instead of ARPACK
  Vector eigenvalues;             // ascending; as many as converged (== count on success)
  Matrix eigenvectors;            // n x eigenvalues.size(), columns B-orthonormal
  int iterations = 0;             // ARPACK restarts taken (0 for dense)
  int converged = 0;              // number of converged pairs returned
  int operator_applications = 0;  // solves with (A - sigma B) (0 for dense)
  double shift = 0.0;             // sigma used (0 for dense)
  std::string message;            // what happened (ARPACK info codes translated), never empty
};

// Throws std::invalid_argument when A or B is not square, their sizes differ, count is not in
// [1, n - 1], or options are out of range (ncv given and not in (count, n], tolerance < 0,
// max_iterations < 1). Numerical failures (factorization, ARPACK errors, no convergence) do not
// throw: they come back with success = false and a message.
GeneralizedEigenResult generalized_eigenpairs(const SparseMatrix& A, const SparseMatrix& B, int count,
                                              const GeneralizedEigenOptions& options = {});

}  // namespace tailor
