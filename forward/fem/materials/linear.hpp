#pragma once
// Linear (small-strain) isotropic elasticity:
//   Psi = lambda/2 tr(eps)^2 + mu tr(eps^2),   eps = (F + F^T)/2 - I,
//   P = lambda tr(eps) I + 2 mu eps,   dP/dF = lambda vec(I) vec(I)^T + mu (I + K),
// K the commutation matrix. Not rotation invariant; the reference every nonlinear material
// must agree with to first order at F = I. Plane strain (Dim = 2): eps_33 = 0 at diag(F, 1),
// so the same formulas hold with Dim x Dim matrices.
#include "forward/fem/material.hpp"

namespace tailor {

template <int Dim>
class LinearMaterial final : public Material<Dim> {
 public:
  using typename Material<Dim>::Mat;
  std::string name() const override { return "linear"; }
  bool tangent_is_constant() const override { return true; }
  // The tangent is constant. Its eigenvalues are 0 (skew modes), 2 mu (deviatoric symmetric)
  // and Dim lambda + 2 mu (trace mode); the projected tangent clamps the last two analytically.
  void evaluate(const Mat& F, const LameParameters& lame, bool want_stress, bool want_tangent,
                HessianMode mode, MaterialEvaluation<Dim>& out) const override;
  void lame_derivatives(const Mat& F, const LameParameters& lame,
                        MaterialLameDerivatives<Dim>& out) const override;
};

extern template class LinearMaterial<2>;
extern template class LinearMaterial<3>;

}  // namespace tailor
