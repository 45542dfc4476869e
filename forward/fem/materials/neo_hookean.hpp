#pragma once
// Stable Neo-Hookean of Smith, de Goes, Kim 2018, "Stable Neo-Hookean Flesh Simulation"
// (ACM TOG 37(2)): finite and smooth for every F, including inverted (J <= 0) and F = 0:
//   Psi = mu'/2 (I_C - 3) + lambda'/2 (J - alpha)^2 - mu'/2 log(I_C + 1) - Psi_0,
// I_C = tr(F^T F), J = det F, Psi_0 the constant that makes Psi(I) = 0.
//
// Internal constants (derived here; they match the paper). With cof F = dJ/dF,
//   P = mu' (1 - 1/(I_C + 1)) F + lambda' (J - alpha) cof F.
//  (a) Stress-free rest state, I_C = 3, J = 1, cof I = I: (3/4) mu' + lambda' (1 - alpha) = 0,
//      so alpha = 1 + 3 mu' / (4 lambda')  (= 1 + mu'/lambda' - mu'/(4 lambda')).
//  (b) At F = I, using d cof = tr(dF) I - dF^T there:
//      dP = (3/4) mu' (dF + dF^T) + (lambda' + mu'/8 - (3/4) mu') tr(dF) I,
//      and linear elasticity is mu (dF + dF^T) + lambda tr(dF) I, so
//      mu' = 4/3 mu,  lambda' = lambda + 5/8 mu' = lambda + 5/6 mu,  alpha = 1 + mu / lambda'.
// Plane strain (Dim = 2) is the density at diag(F, 1): I_C = |F|^2 + 1, J = det F (2x2). Then
// I_C = 3, J = 1 and cof = I still hold at rest and d cof = tr(dF) I - dF^T holds in 2D, so (a)
// and (b) give the same constants and plane-strain linear elasticity in the plane.
//
// With these constants (lambda' (J - alpha) = lambda' (J - 1) - mu) the energy is linear in
// the physical (lambda, mu), which keeps the Lame derivatives exact and simple:
//   Psi = (2/3) mu (x - log(1 + x/4)) + (lambda + 5/6 mu)/2 (J - 1)^2 - mu (J - 1),  x = I_C - 3,
//   P   = (4/3) mu I_C/(I_C + 1) F + ((lambda + 5/6 mu)(J - 1) - mu) cof F,
//   dP/dF = a I + b vec(F) vec(F)^T + lambda' vec(cof) vec(cof)^T + s d vec(cof)/d vec(F),
//   a = mu' I_C/(I_C + 1), b = 2 mu'/(I_C + 1)^2, s = lambda' (J - 1) - mu.
// Projected tangent: returned as is when a Cholesky factorisation accepts it (PSD); otherwise
// the negative modes of the analytic eigen-system in the SVD frame are removed (see
// isotropic_projection.hpp: eigenvalues a +- s sigma_k on twists/flips, sigma_k = 1 in plane
// strain, and a Dim x Dim scaling block), which equals clamping the eigenvalues to zero.
// The expanded form never divides by lambda'; the paper's alpha = 1 + mu/lambda' needs
// lambda' > 0, which holds for every E > 0, -1 < nu < 1/2 (lambda' = mu (2 nu/(1 - 2 nu) + 5/6)
// > 0 iff nu > -5/2).
#include "forward/fem/material.hpp"

namespace tailor {

// The internal constants of the stable Neo-Hookean for physical Lame parameters.
struct StableNeoHookeanConstants {
  double lambda;       // lambda' = lambda + 5/6 mu
  double mu;           // mu' = 4/3 mu
  double alpha;        // 1 + 3 mu' / (4 lambda') = 1 + mu / lambda'
  double rest_energy;  // Psi_0 = lambda'/2 (1 - alpha)^2 - mu'/2 log 4 (the unshifted energy at F = I)
};
StableNeoHookeanConstants stable_neo_hookean_constants(const LameParameters& lame);

template <int Dim>
class NeoHookeanMaterial final : public Material<Dim> {
 public:
  using typename Material<Dim>::Mat;
  std::string name() const override { return "neo_hookean"; }
  void evaluate(const Mat& F, const LameParameters& lame, bool want_stress, bool want_tangent,
                HessianMode mode, MaterialEvaluation<Dim>& out) const override;
  void lame_derivatives(const Mat& F, const LameParameters& lame,
                        MaterialLameDerivatives<Dim>& out) const override;
  // Block (a, b) of V B^T T B is V [a (g_a.g_b) I + b (F g_a)(F g_b)^T + lambda' (C g_a)(C g_b)^T
  // + s dJ-term], C = cof F, with the determinant's second derivative contracted in closed form
  // (3D: s eps_ikm (F (g_a x g_b))_m). About a quarter of the flops of forming T and B^T T B.
  bool has_simplex_hessian() const override { return true; }
  void simplex_hessian(const Mat& F, const LameParameters& lame, const typename Material<Dim>::NodeGradients& G,
                       double V, double* H) const override;
};

extern template class NeoHookeanMaterial<2>;
extern template class NeoHookeanMaterial<3>;

}  // namespace tailor
