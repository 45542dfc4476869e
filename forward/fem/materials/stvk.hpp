#pragma once
// Saint Venant-Kirchhoff: linear elasticity on the Green strain,
//   Psi = lambda/2 tr(E)^2 + mu tr(E^2),   E = (F^T F - I)/2,
//   P = F S,   S = lambda tr(E) I + 2 mu E,
//   dP_ij/dF_kl = delta_ik S_lj + lambda F_ij F_kl + mu delta_jl (F F^T)_ik + mu F_il F_kj.
// Rotation invariant; not robust under compression (it softens and admits inverted minima).
// Plane strain (Dim = 2): at diag(F, 1) the Green strain has E_33 = E_i3 = 0, so the same
// formulas hold with Dim x Dim matrices.
#include "forward/fem/material.hpp"

namespace tailor {

template <int Dim>
class StvkMaterial final : public Material<Dim> {
 public:
  using typename Material<Dim>::Mat;
  std::string name() const override { return "stvk"; }
  // Projected tangent: unchanged when a Cholesky factorisation accepts it; otherwise the negative
  // modes of the analytic eigen-system in the SVD frame are removed (see stvk.cpp and
  // isotropic_projection.hpp), which equals clamping the eigenvalues to zero.
  void evaluate(const Mat& F, const LameParameters& lame, bool want_stress, bool want_tangent,
                HessianMode mode, MaterialEvaluation<Dim>& out) const override;
  void lame_derivatives(const Mat& F, const LameParameters& lame,
                        MaterialLameDerivatives<Dim>& out) const override;
};

extern template class StvkMaterial<2>;
extern template class StvkMaterial<3>;

}  // namespace tailor
