#pragma once
// Example deformations for example-based damping (Xu & Barbic 2017; docs/methods.md section 6):
// displacement fields [length] in full DOF space (interleaved like x), from user arrays,
// from eigenmodes of the rest stiffness (K phi = lambda M phi on the free DOFs), or as the
// linear static response to given loads (K u = f on the free DOFs). They are mass-
// orthonormalized before use (U^T M U = I) by Gram-Schmidt in the M inner product, in the
// given order: example i keeps only its part M-orthogonal to examples 0..i-1.
#include <vector>

#include "forward/core/types.hpp"

namespace tailor {

// Columns of `examples` (n x r) -> M-orthonormal columns spanning the same space, in order.
// Throws std::invalid_argument naming the example when one is zero or (numerically) a linear
// combination of the earlier ones: its M-orthogonal remainder is below `tolerance` times its
// M-norm.
Matrix mass_orthonormalize(const Matrix& examples, const SparseMatrix& mass, double tolerance = 1e-8);

// Eigenmodes number `indices` (0 = lowest frequency) of K phi = lambda M phi restricted to
// the free DOFs x = x0 + S y, expanded to full space (zero on fixed DOFs), M-orthonormal.
// stiffness, mass: full n x n; basis: S (n x m). Throws std::runtime_error when the
// eigensolver fails and std::invalid_argument for a negative index.
Matrix eigenmode_examples(const SparseMatrix& stiffness, const SparseMatrix& mass, const SparseMatrix& basis,
                          const std::vector<int>& indices, Vector* eigenvalues = nullptr);

// Linear static responses u = S (S^T K S)^{-1} S^T f to the columns f of `loads` (n x r,
// nodal forces [force]). Throws std::runtime_error when S^T K S is singular.
Matrix static_response_examples(const SparseMatrix& stiffness, const SparseMatrix& basis,
                                const Matrix& loads);

}  // namespace tailor
