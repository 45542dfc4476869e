#include "forward/fem/materials/neo_hookean.hpp"

#include <Eigen/LU>
#include <cmath>

#include "forward/core/psd_projection.hpp"
#include "forward/fem/material_registry.hpp"
#include "forward/fem/materials/isotropic_projection.hpp"
#include "forward/fem/materials/rotation_variant_svd.hpp"
#include "forward/fem/materials/tensor_ops.hpp"

namespace tailor {
namespace md = material_detail;
namespace {

// Invariants of the density at diag(F, 1) (plane strain) or F (3D). x = I_C - 3 is formed
// as |F - I|^2 + 2 tr(F - I) (+ 0 for the pinned F_33 = 1) to avoid cancellation near rest.
template <int Dim>
struct Invariants {
  double x;    // I_C - 3
  double Ic;   // I_C
  double Jm1;  // J - 1
  md::Mat<Dim> cof;
};

template <int Dim>
Invariants<Dim> invariants(const md::Mat<Dim>& F) {
  Invariants<Dim> v;
  const md::Mat<Dim> G = F - md::Mat<Dim>::Identity();
  v.x = G.squaredNorm() + 2.0 * G.trace();
  v.Ic = v.x + 3.0;
  v.Jm1 = F.determinant() - 1.0;
  v.cof = md::cofactor(F);
  return v;
}

// Removes the negative modes of the tangent a I + b f f^T + lambda' g g^T + s d(cof F)/dF using
// its analytic eigen-system in the (signed) SVD frame. J = s0 s1 s2 (3D) or s0 s1 (plane strain,
// the pinned third stretch being 1) has Hessian eigenvalues +sigma_k on twist_ij and -sigma_k on
// flip_ij (k the third index; sigma_k = 1 in plane strain), and on the scaling subspace
// M_ij = sigma_k (i != j), M_ii = 0. So the tangent has a + s sigma_k (twist), a - s sigma_k
// (flip) and a I + b sigma sigma^T + lambda' g g^T + s M on scaling, g = dJ/dsigma.
template <int Dim>
void project(const md::Mat<Dim>& F, double a, double b, double lambda_s, double s, md::Tangent<Dim>& T) {
  using Modes = md::IsotropicModes<Dim>;
  md::RotationVariantSvd<Dim> svd;
  md::rotation_variant_svd(F, svd);
  const Eigen::Matrix<double, Dim, 1>& sg = svd.sigma;
  Eigen::Matrix<double, Dim, 1> dJ;
  if constexpr (Dim == 3) {
    dJ << sg(1) * sg(2), sg(0) * sg(2), sg(0) * sg(1);
  } else {
    dJ << sg(1), sg(0);
  }
  Modes modes;
  modes.scaling.noalias() = b * sg * sg.transpose();
  modes.scaling.noalias() += lambda_s * dJ * dJ.transpose();
  modes.scaling.diagonal().array() += a;
  for (int p = 0; p < Modes::kPairs; ++p) {
    const int i = Modes::first(p), j = Modes::second(p);
    const double sk = Dim == 3 ? sg(3 - i - j) : 1.0;
    modes.twist(p) = a + s * sk;
    modes.flip(p) = a - s * sk;
    modes.scaling(i, j) += s * sk;
    modes.scaling(j, i) += s * sk;
  }
  md::subtract_negative_modes<Dim>(svd, modes, T);
}

}  // namespace

StableNeoHookeanConstants stable_neo_hookean_constants(const LameParameters& lame) {
  StableNeoHookeanConstants k;
  k.lambda = lame.lambda + 5.0 / 6.0 * lame.mu;
  k.mu = 4.0 / 3.0 * lame.mu;
  k.alpha = 1.0 + 0.75 * k.mu / k.lambda;
  k.rest_energy = 0.5 * k.lambda * (1.0 - k.alpha) * (1.0 - k.alpha) - 0.5 * k.mu * std::log(4.0);
  return k;
}

template <int Dim>
void NeoHookeanMaterial<Dim>::evaluate(const Mat& F, const LameParameters& lame, bool want_stress,
                                       bool want_tangent, HessianMode mode,
                                       MaterialEvaluation<Dim>& out) const {
  const double mu_s = 4.0 / 3.0 * lame.mu;                    // mu'
  const double lambda_s = lame.lambda + 5.0 / 6.0 * lame.mu;  // lambda'
  const Invariants<Dim> v = invariants<Dim>(F);
  // Psi = mu'/2 (x - log(1 + x/4)) + lambda'/2 (J-1)^2 - mu (J-1): the paper's density minus Psi_0,
  // since lambda'/2 ((J - alpha)^2 - (1 - alpha)^2) = lambda'/2 (J-1)^2 - lambda' (alpha-1) (J-1).
  out.energy_density =
      0.5 * mu_s * (v.x - std::log1p(0.25 * v.x)) + 0.5 * lambda_s * v.Jm1 * v.Jm1 - lame.mu * v.Jm1;
  if (!want_stress && !want_tangent) return;
  const double a = mu_s * v.Ic / (v.Ic + 1.0);  // mu' (1 - 1/(I_C + 1))
  const double s = lambda_s * v.Jm1 - lame.mu;  // lambda' (J - alpha)
  if (want_stress) out.stress = a * F + s * v.cof;
  if (want_tangent) {
    const double b = 2.0 * mu_s / ((v.Ic + 1.0) * (v.Ic + 1.0));
    const auto f = md::vec<Dim>(F);
    const auto g = md::vec<Dim>(v.cof);
    auto& T = out.tangent;
    T.noalias() = b * f * f.transpose();
    T.noalias() += lambda_s * g * g.transpose();
    T.diagonal().array() += a;
    md::add_determinant_hessian(s, F, T);
    if (mode == HessianMode::projected && !cholesky_accepts<Dim * Dim>(T)) project(F, a, b, lambda_s, s, T);
  }
}

template <int Dim>
void NeoHookeanMaterial<Dim>::simplex_hessian(const Mat& F, const LameParameters& lame,
                                              const typename Material<Dim>::NodeGradients& G, double V,
                                              double* H) const {
  constexpr int kNodes = Dim + 1;
  const double mu_s = 4.0 / 3.0 * lame.mu;
  const double lambda_s = lame.lambda + 5.0 / 6.0 * lame.mu;
  const Invariants<Dim> v = invariants<Dim>(F);
  // The same coefficients as the tangent in evaluate(), scaled by the volume.
  const double a = V * mu_s * v.Ic / (v.Ic + 1.0);
  const double s = V * (lambda_s * v.Jm1 - lame.mu);
  const double b = V * 2.0 * mu_s / ((v.Ic + 1.0) * (v.Ic + 1.0));
  const double l = V * lambda_s;
  const Eigen::Matrix<double, Dim, kNodes> FG = F * G.transpose();      // column a: F g_a
  const Eigen::Matrix<double, Dim, kNodes> CG = v.cof * G.transpose();  // column a: cof(F) g_a
  Eigen::Map<Eigen::Matrix<double, Dim * kNodes, Dim * kNodes>> out(H);
  for (int na = 0; na < kNodes; ++na)
    for (int nb = na; nb < kNodes; ++nb) {
      md::Mat<Dim> block = b * FG.col(na) * FG.col(nb).transpose();
      block.noalias() += l * CG.col(na) * CG.col(nb).transpose();
      block.diagonal().array() += a * G.row(na).dot(G.row(nb));
      // d2J/dF_ij dF_kl contracted with g_a[j] g_b[l].
      if constexpr (Dim == 3) {
        const Eigen::Vector3d w = s * (F * G.row(na).transpose().cross(G.row(nb).transpose()));
        block(0, 1) += w(2);
        block(1, 0) -= w(2);
        block(2, 0) += w(1);
        block(0, 2) -= w(1);
        block(1, 2) += w(0);
        block(2, 1) -= w(0);
      } else {
        const double c = s * (G(na, 0) * G(nb, 1) - G(na, 1) * G(nb, 0));
        block(0, 1) += c;
        block(1, 0) -= c;
      }
      out.template block<Dim, Dim>(Dim * na, Dim * nb) = block;
      if (nb != na) out.template block<Dim, Dim>(Dim * nb, Dim * na) = block.transpose();
    }
}

template <int Dim>
void NeoHookeanMaterial<Dim>::lame_derivatives(const Mat& F, const LameParameters& /*lame*/,
                                               MaterialLameDerivatives<Dim>& out) const {
  // Psi and P are linear in (lambda, mu); see the header for the expanded form.
  const Invariants<Dim> v = invariants<Dim>(F);
  const double shape = v.x - std::log1p(0.25 * v.x);
  out.energy_density << 0.5 * v.Jm1 * v.Jm1, 2.0 / 3.0 * shape + 5.0 / 12.0 * v.Jm1 * v.Jm1 - v.Jm1;
  const Mat dP_dlambda = v.Jm1 * v.cof;
  const Mat dP_dmu = 4.0 / 3.0 * v.Ic / (v.Ic + 1.0) * F + (5.0 / 6.0 * v.Jm1 - 1.0) * v.cof;
  out.stress.col(0) = md::vec<Dim>(dP_dlambda);
  out.stress.col(1) = md::vec<Dim>(dP_dmu);
}

template class NeoHookeanMaterial<2>;
template class NeoHookeanMaterial<3>;

// The registry's entry (forward/fem/material_registry.hpp).
MaterialEntry neo_hookean_material_entry() {
  return make_material_entry<NeoHookeanMaterial>(
      "neo_hookean", "stable Neo-Hookean (Smith, de Goes and Kim 2018), finite for inverted elements",
      {.polynomial_in_deformation = false});
}

}  // namespace tailor
