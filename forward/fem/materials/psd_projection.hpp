#pragma once
// Projection of a small symmetric matrix onto the positive semidefinite cone (private to
// forward/fem/materials): A <- V max(D, 0) V^T, the nearest PSD matrix in the Frobenius norm.
#include <Eigen/Core>

namespace tailor::material_detail {

// Fast path: when A + delta I has a Cholesky factorisation, with delta = kPsdShift * max_i |A_ii|,
// A is returned unchanged (its eigenvalues are then >= -delta, i.e. PSD up to round-off; this
// also covers tangents that are PSD but exactly singular, like rigid-rotation modes at rest).
// Otherwise the symmetric eigen-decomposition is clamped. Fixed sizes only, no allocation.
// Returns true when the eigen-decomposition was needed.
inline constexpr double kPsdShift = 1e-12;

// The fast-path test alone: true when A + kPsdShift * max_i |A_ii| I has a Cholesky factorisation.
template <int N>
bool cholesky_accepts(const Eigen::Matrix<double, N, N>& A);

template <int N>
bool project_psd(Eigen::Matrix<double, N, N>& A);

extern template bool cholesky_accepts<4>(const Eigen::Matrix<double, 4, 4>&);
extern template bool cholesky_accepts<9>(const Eigen::Matrix<double, 9, 9>&);
extern template bool project_psd<4>(Eigen::Matrix<double, 4, 4>&);
extern template bool project_psd<9>(Eigen::Matrix<double, 9, 9>&);

}  // namespace tailor::material_detail
