#pragma once
// A mass-orthonormal basis of the span of given vectors, with near-duplicates removed: the
// reduced bases of model reduction (linear modes, modal derivatives, Krylov blocks) are
// gathered from several sources whose spans overlap.
#include <vector>

#include "forward/core/types.hpp"

namespace tailor {

// Columns of `vectors` (n x c, in the space of `mass`, n x n SPD) are M-orthogonalized in
// order by modified Gram-Schmidt, twice (re-orthogonalization keeps round-off at machine
// level). A column whose M-norm after removing its components along the kept ones is below
// drop_tolerance times its M-norm before is dropped as a (near-)duplicate, as is a zero
// column. Returns the n x k basis, B^T M B = I; `kept` (optional) receives the indices of the
// input columns that produced each basis column. Throws std::invalid_argument on size
// mismatch or drop_tolerance outside (0, 1).
Matrix mass_orthonormal_basis(const Matrix& vectors, const SparseMatrix& mass, double drop_tolerance = 1e-6,
                              std::vector<int>* kept = nullptr);

}  // namespace tailor
