#pragma once
// Non-negative least squares, min |A x - b| subject to x >= 0, by the active-set method of
// Lawson and Hanson ("Solving Least Squares Problems", 1974, chapter 23, algorithm NNLS): the
// passive set P grows by the free index of largest dual w = A^T (b - A x); an unconstrained
// least-squares solve on P replaces x, and where that solve leaves P's box, x moves back to
// the boundary and the indices that reach zero leave P. Each least-squares solve is a
// column-pivoted QR of A restricted to P (dense; the cubature fits have a few hundred columns).
#include "forward/core/types.hpp"

namespace tailor {

struct NnlsResult {
  Vector x;               // >= 0
  double residual = 0.0;  // |A x - b|
  int iterations = 0;     // outer iterations (indices moved into P)
  bool converged = false; // the Karush-Kuhn-Tucker conditions hold to the tolerance
};

// Throws std::invalid_argument when b has not A.rows() entries. max_iterations <= 0: 3 n + 10.
// start: a feasible point (>= 0) whose support is the first passive set (a warm start, e.g.
// the previous solution when a column was appended); null: x = 0.
NnlsResult nnls(const Matrix& a, const Vector& b, int max_iterations = 0, const Vector* start = nullptr);

}  // namespace tailor
