#pragma once
// Linear corotated elasticity:
//   Psi = mu ||F - R||^2 + lambda/2 tr(R^T F - I)^2,
// with R the rotation of the polar decomposition, continued through inversion by the
// rotation-variant SVD F = U Sigma V^T (det U = det V = 1, the reflection carried by the sign of
// the smallest singular value; Irving et al. 2004). Then R = U V^T maximises tr(R^T F) over
// rotations, tr(R^T F) = sum_i sigma_i and ||F - R||^2 = sum_i (sigma_i - 1)^2.
//
// Stress: since R^T dR is skew and R^T F = V Sigma V^T is symmetric, F : dR = R : dR = 0, so
//   P = 2 mu (F - R) + lambda c R,   c = tr(R^T F) - Dim_3d,   (d tr(R^T F)/dF = R).
// Tangent: dP = 2 mu dF + lambda (R : dF) R + (lambda c - 2 mu) dR, and dR/dF is
//   dR/dF = sum_{i<j} 2/(sigma_i + sigma_j) t_ij t_ij^T,  t_ij = vec(u_i v_j^T - u_j v_i^T)/sqrt(2),
// zero on the stretch and symmetric-flip modes. Hence the eigen-system of the tangent is known
// in closed form: 2 mu on the flips and the deviatoric stretches, 2 mu + 3 lambda (3D) on
// vec(R)/sqrt(3), 2 mu + 2 (lambda c - 2 mu)/(sigma_i + sigma_j) on the twists; the projected
// tangent clamps these analytically (no eigen-solver).
//
// Guard: sigma_i + sigma_j >= 0 always (only the smallest may be negative). At
// sigma_i + sigma_j = 0 (e.g. F a scaled reflection) R is not unique and not differentiable, so
// no exact tangent exists; the twist denominator is floored at kTwistFloor * max(1, sigma_0).
// The energy and stress stay exact (for the R returned); the tangent is exact wherever
// sigma_i + sigma_j is above the floor and finite (large) below it.
//
// Plane strain (Dim = 2): R = diag(R2, 1), R2 the 2D rotation maximising tr(R2^T F) (closed
// form, angle atan2(F10 - F01, F00 + F11), no SVD). This equals the 3D density at diag(F, 1)
// whenever det F > 0, and for det F < 0 as long as the smaller in-plane singular value is <= 1.
// When det F < 0 and both in-plane singular values exceed 1, the 3D rotation-variant SVD of
// diag(F, 1) would put the reflection on the pinned out-of-plane axis (R_33 = -1): its stress
// then jumps across |sigma_1| = 1 and pulls the element towards staying inverted. We keep the
// reflection in-plane instead (a deliberate deviation, documented here).
#include "forward/fem/material.hpp"

namespace tailor {

template <int Dim>
class CorotatedMaterial final : public Material<Dim> {
 public:
  using typename Material<Dim>::Mat;
  // Relative floor on sigma_i + sigma_j in the twist coefficients of the tangent.
  static constexpr double kTwistFloor = 1e-8;

  std::string name() const override { return "corotated"; }
  void evaluate(const Mat& F, const LameParameters& lame, bool want_stress, bool want_tangent,
                HessianMode mode, MaterialEvaluation<Dim>& out) const override;
  void lame_derivatives(const Mat& F, const LameParameters& lame,
                        MaterialLameDerivatives<Dim>& out) const override;

  // The rotation R used for F (exposed for tests).
  static Mat rotation(const Mat& F);
};

extern template class CorotatedMaterial<2>;
extern template class CorotatedMaterial<3>;

}  // namespace tailor
