#pragma once
// Projection of a small symmetric matrix onto the positive semidefinite cone,
// A <- V max(D, 0) V^T (the nearest PSD matrix in the Frobenius norm), for the per-element and
// per-stencil Hessians of Newton's projected mode (Teran et al. 2005 for elements; Li et al.
// 2020, section 5, for contact stencils). Every term that projects uses this one function:
// materials, contact, tori, rigid bodies and rods.
//
// Fast path: when A + delta I has a Cholesky factorization, with delta = kPsdShift * max_i |A_ii|,
// A is left unchanged (its eigenvalues are then >= -delta, PSD up to round-off; this also keeps
// tangents that are PSD but exactly singular, like rigid modes at rest). Otherwise the symmetric
// eigen-decomposition is clamped. The work is done in one compiled function for every size
// (forward/core/psd_projection.cpp), so no caller instantiates an eigen-solver of its own.
// Tests: tests/forward/core/psd_projection_test.cpp.
#include <Eigen/Core>

namespace tailor {

inline constexpr double kPsdShift = 1e-12;

namespace psd_detail {
// The column-major n x n symmetric matrix at `a`.
bool cholesky_accepts(const double* a, int n);
bool project_psd(double* a, int n);
}  // namespace psd_detail

// True when A + kPsdShift * max_i |A_ii| I has a Cholesky factorization (A is then PSD up to
// round-off). A zero diagonal passes only when A = 0.
template <int N>
bool cholesky_accepts(const Eigen::Matrix<double, N, N>& A) {
  return psd_detail::cholesky_accepts(A.data(), static_cast<int>(A.rows()));
}

// Projects A in place; returns true when the eigen-decomposition was needed (A changed).
template <int N>
bool project_psd(Eigen::Matrix<double, N, N>& A) {
  return psd_detail::project_psd(A.data(), static_cast<int>(A.rows()));
}

}  // namespace tailor
