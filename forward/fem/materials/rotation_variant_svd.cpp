#include "forward/fem/materials/rotation_variant_svd.hpp"

#include <Eigen/LU>
#include <cmath>
// GCC 12 reports a false -Wmaybe-uninitialized inside Eigen's fixed-size JacobiSVD once it is
// inlined here (all of JacobiSVD's members are written before use); silenced for this file only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <Eigen/SVD>

namespace tailor::material_detail {

void rotation_variant_svd(const Eigen::Matrix3d& F, RotationVariantSvd<3>& out) {
  // Square input: no QR preconditioner needed. Fixed size, so no heap allocation.
  const Eigen::JacobiSVD<Eigen::Matrix3d, Eigen::NoQRPreconditioner> svd(
      F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  out.U = svd.matrixU();
  out.V = svd.matrixV();
  out.sigma = svd.singularValues();  // sorted, non-negative
  // Turn each improper factor into a rotation by flipping its last column; the sign moves to
  // the smallest singular value so that U diag(sigma) V^T is still F.
  if (out.U.determinant() < 0.0) {
    out.U.col(2) *= -1.0;
    out.sigma(2) *= -1.0;
  }
  if (out.V.determinant() < 0.0) {
    out.V.col(2) *= -1.0;
    out.sigma(2) *= -1.0;
  }
}

void rotation_variant_polar_2d(const Eigen::Matrix2d& F, Eigen::Matrix2d& R, double& tau) {
  // tr(R(t)^T F) = cos(t) (F00 + F11) + sin(t) (F10 - F01), maximal at t = atan2(b, a).
  const double a = F(0, 0) + F(1, 1), b = F(1, 0) - F(0, 1);
  tau = std::hypot(a, b);
  const double cs = tau > 0.0 ? a / tau : 1.0, sn = tau > 0.0 ? b / tau : 0.0;
  R << cs, -sn, sn, cs;
}

void rotation_variant_svd(const Eigen::Matrix2d& F, RotationVariantSvd<2>& out) {
  Eigen::Matrix2d R;
  double tau = 0.0;
  rotation_variant_polar_2d(F, R, tau);
  const Eigen::Matrix2d S = R.transpose() * F;  // symmetric up to round-off
  const double p = S(0, 0), r = S(1, 1), q = 0.5 * (S(0, 1) + S(1, 0));
  // Eigenvalues m +- d of [p q; q r]; the larger one has eigenvector (cos t, sin t),
  // t = atan2(2q, p - r)/2. Since sigma_0 + sigma_1 = tau >= 0, sigma_0 >= |sigma_1|.
  const double m = 0.5 * (p + r), d = std::hypot(0.5 * (p - r), q);
  const double t = 0.5 * std::atan2(2.0 * q, p - r);
  const double c = std::cos(t), s = std::sin(t);
  out.V << c, -s, s, c;
  out.U.noalias() = R * out.V;
  out.sigma << m + d, m - d;
}

}  // namespace tailor::material_detail
