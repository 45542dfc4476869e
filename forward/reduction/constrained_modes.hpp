#pragma once
// Vibration modes under linear equality constraints (Xu & Barbic 2016, "Pose-space subspace
// dynamics", section 6: contacts of an example pose become bilateral constraints):
//
//   K phi = lambda M phi,   C phi = 0,
//
// solved by null-space projection (docs/methods.md section 17): with N a basis of null(C),
// (N^T K N) y = lambda (N^T M N) y and phi = N y (ARPACK shift-invert through
// generalized_eigenpairs). N is sparse: a column-pivoted QR of C, C P = Q [R1 R2], gives
// N = P [-R1^{-1} R2; I], whose dense block only has columns where C has entries, so N^T K N keeps
// K's sparsity away from the constrained DOFs. By Cauchy interlacing for m independent
// constraints, lambda_k <= lambda~_k <= lambda_{k+m} (the unconstrained eigenvalues lambda).
#include "forward/core/types.hpp"
#include "forward/reduction/generalized_eigen.hpp"

namespace tailor {

// A basis of null(C), n x (n - rank C), sparse; rank decided with relative tolerance
// `tolerance` on the QR diagonal. `rank` (optional) receives rank C.
SparseMatrix constraint_null_space(const Matrix& constraints, double tolerance = 1e-10, int* rank = nullptr);

struct ConstrainedModes {
  Vector eigenvalues;  // ascending
  Matrix modes;        // n x count, modes^T M modes = I, C modes = 0
  int constraint_rank = 0;
  GeneralizedEigenResult solve;  // on the projected problem (eigenvectors moved out)
};

// K, M: n x n symmetric (full storage), M positive definite; C: m x n. Throws
// std::invalid_argument for sizes or count outside [1, n - rank C - 1], std::runtime_error when
// the eigen solve fails.
ConstrainedModes constrained_modes(const SparseMatrix& stiffness, const SparseMatrix& mass, const Matrix& constraints,
                                   int count, const GeneralizedEigenOptions& options = {});

}  // namespace tailor
