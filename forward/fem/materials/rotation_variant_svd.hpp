#pragma once
// Rotation-variant SVD (private to forward/fem/materials), after Irving, Teran, Fedkiw 2004,
// "Invertible finite elements for robust simulation of large deformation":
// F = U diag(sigma) V^T with U, V proper rotations (det = +1), sigma sorted by decreasing
// magnitude, and a reflection (det F < 0) carried by the sign of the smallest singular value.
// Then R = U V^T is the rotation maximising tr(R^T F) over rotations, i.e. the rotation of the
// polar decomposition for det F > 0, continued through inversion; sigma_i + sigma_j >= 0.
#include <Eigen/Core>

namespace tailor::material_detail {

template <int Dim>
struct RotationVariantSvd {
  Eigen::Matrix<double, Dim, Dim> U;
  Eigen::Matrix<double, Dim, Dim> V;
  Eigen::Matrix<double, Dim, 1> sigma;  // sigma_0 >= ... >= |sigma_last|, only the last may be < 0
};

// 3D: Eigen's JacobiSVD on the fixed 3x3 matrix, then the sign fix-up.
void rotation_variant_svd(const Eigen::Matrix3d& F, RotationVariantSvd<3>& out);
// 2D, closed form: R from the angle atan2(F10 - F01, F00 + F11), then the symmetric 2x2
// eigen-decomposition of R^T F = V diag(sigma) V^T, U = R V.
void rotation_variant_svd(const Eigen::Matrix2d& F, RotationVariantSvd<2>& out);
// The 2D rotation alone: R maximising tr(R^T F); tau = max tr(R^T F) = sigma_0 + sigma_1 >= 0.
// For tau = 0 (F a scaled reflection) every rotation attains it and R = I is returned.
void rotation_variant_polar_2d(const Eigen::Matrix2d& F, Eigen::Matrix2d& R, double& tau);

}  // namespace tailor::material_detail
