#pragma once
// Conjugate gradients on H v = rhs, H symmetric given by its upper triangle, preconditioned by
// the Cholesky factor of a nearby positive definite matrix (the previous Newton iterate's
// Hessian, or a neighbouring time step's). The adjoints use it to reuse factorizations.
#include "forward/solve/sparse_cholesky.hpp"

namespace tailor {

struct PcgResult {
  bool converged = false;          // ||rhs - H v|| <= relative_tolerance ||rhs||
  int iterations = 0;              // preconditioner applications after the first (1 also when the
                                   // first one met the tolerance and no other was made)
  double relative_residual = 0.0;  // ||rhs - H v|| / ||rhs|| of the returned v
  double initial_relative_residual = 0.0;  // the same for v = P^-1 rhs, the preconditioner's solve
};

// `solution` is overwritten. Stops early (not converged) on non-positive curvature.
PcgResult preconditioned_cg(const SparseMatrix& upper, const SparseCholesky& preconditioner,
                            const Vector& rhs, double relative_tolerance, int max_iterations,
                            Vector& solution);

}  // namespace tailor
