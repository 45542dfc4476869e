#pragma once
// Rotation by a rotation vector (Rodrigues' formula) with exact first and second derivatives:
//   R(w) = I + a(s) [w] + b(s) [w]^2,   s = |w|^2 = theta^2,
//   a = sin(theta) / theta,   b = (1 - cos(theta)) / theta^2,
// ([w] the cross-product matrix; docs/methods.md section 10 writes b = 2 sinc^2(theta / 2) / 2).
// a and b are taken as functions of s, which are smooth (entire) in s: a Taylor series for
// s < 1 keeps them and their s-derivatives accurate to round-off near w = 0, the closed
// forms are used beyond. Exact for any angle; the parameterization itself degenerates at
// theta = 2 pi (R = I for a whole sphere of w), so rigid bodies keep |w| < 2 pi.
#include <Eigen/Core>
#include <array>

namespace tailor::rigid {

struct RotationDerivatives {
  Eigen::Matrix3d rotation;                              // R
  std::array<Eigen::Matrix3d, 3> first;                  // dR / dw_k
  std::array<std::array<Eigen::Matrix3d, 3>, 3> second;  // d2R / dw_k dw_l (symmetric in k, l)
};

Eigen::Matrix3d rotation_matrix(const Eigen::Vector3d& w);
RotationDerivatives rotation_derivatives(const Eigen::Vector3d& w);
// A rotation vector of R (|w| < 2 pi): of the representatives w + 2 pi k w / |w|, the one
// nearest to `near` (so that a sequence of rotations gets a continuous sequence of vectors).
Eigen::Vector3d rotation_vector(const Eigen::Matrix3d& R,
                                const Eigen::Vector3d& near = Eigen::Vector3d::Zero());

// vee of the skew part of A: 1/2 (A_32 - A_23, A_13 - A_31, A_21 - A_12) (for A = R dR^T, the
// angular velocity; for A = R Rb^T with Rb a reference rotation, sin(angle) times its axis).
// The cross-product matrix [a]x: [a]x b = a x b.
inline Eigen::Matrix3d cross_matrix(const Eigen::Vector3d& a) {
  Eigen::Matrix3d k;
  k << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return k;
}

inline Eigen::Vector3d skew_vee(const Eigen::Matrix3d& A) {
  return 0.5 * Eigen::Vector3d(A(2, 1) - A(1, 2), A(0, 2) - A(2, 0), A(1, 0) - A(0, 1));
}

// a(s), b(s) and their first and second derivatives in s (exposed for tests).
struct RodriguesCoefficients {
  double a, da, d2a, b, db, d2b;
};
RodriguesCoefficients rodrigues_coefficients(double s);

}  // namespace tailor::rigid
