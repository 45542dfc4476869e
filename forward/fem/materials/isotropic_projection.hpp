#pragma once
// PSD projection of the tangent of an isotropic energy from its eigen-system in the SVD frame
// (private to forward/fem/materials; the structure is the one used by Smith, de Goes, Kim 2019,
// "Analytic Eigensystems for Isotropic Distortion Energies").
//
// For Psi(F) = Psi(sigma) with F = U diag(sigma) V^T (rotation-variant SVD) and
// psi_i = dPsi/dsigma_i, the tangent is block diagonal in the orthonormal basis
//   twist_ij = vec(u_i v_j^T - u_j v_i^T)/sqrt(2)  eigenvalue (psi_i + psi_j)/(sigma_i + sigma_j),
//   flip_ij  = vec(u_i v_j^T + u_j v_i^T)/sqrt(2)  eigenvalue (psi_i - psi_j)/(sigma_i - sigma_j),
//   scaling  = span vec(u_i v_i^T), where it is the Dim x Dim Hessian d2Psi/dsigma2,
// for the pairs i < j (3 in 3D, 1 in plane strain). Each material supplies these in closed form
// (without removable singularities), and T <- T - sum over negative eigenvalues ev of ev e e^T.
#include <Eigen/Core>

#include "forward/fem/materials/rotation_variant_svd.hpp"

namespace tailor::material_detail {

template <int Dim>
struct IsotropicModes {
  static constexpr int kPairs = Dim == 3 ? 3 : 1;
  // Pair p: (i, j) = pair(p) and k = the remaining index in 3D.
  static constexpr int first(int p) { return p == 2 ? 1 : 0; }
  static constexpr int second(int p) { return p == 0 ? 1 : 2; }
  Eigen::Matrix<double, kPairs, 1> twist;
  Eigen::Matrix<double, kPairs, 1> flip;
  Eigen::Matrix<double, Dim, Dim> scaling;  // d2Psi / dsigma_i dsigma_j
};

template <int Dim>
void subtract_negative_modes(const RotationVariantSvd<Dim>& svd, const IsotropicModes<Dim>& modes,
                             Eigen::Matrix<double, Dim * Dim, Dim * Dim>& T);

extern template void subtract_negative_modes<2>(const RotationVariantSvd<2>&, const IsotropicModes<2>&,
                                                Eigen::Matrix<double, 4, 4>&);
extern template void subtract_negative_modes<3>(const RotationVariantSvd<3>&, const IsotropicModes<3>&,
                                                Eigen::Matrix<double, 9, 9>&);

}  // namespace tailor::material_detail
