#include "forward/fem/materials/stvk.hpp"

#include "forward/core/psd_projection.hpp"
#include "forward/fem/material_registry.hpp"
#include "forward/fem/materials/isotropic_projection.hpp"
#include "forward/fem/materials/rotation_variant_svd.hpp"
#include "forward/fem/materials/tensor_ops.hpp"

namespace tailor {
namespace md = material_detail;
namespace {

// Removes the negative modes of the tangent using its analytic eigen-system in the (signed) SVD
// frame. Psi(sigma) = lambda/2 trE^2 + mu sum E_i^2, E_i = (sigma_i^2 - 1)/2 (the pinned third
// stretch of plane strain has E_33 = 0 and drops out), so with c0 = lambda trE - mu:
// psi_i = sigma_i (c0 + mu sigma_i^2) and
//   twist_ij = (psi_i + psi_j)/(sigma_i + sigma_j) = c0 + mu (s_i^2 - s_i s_j + s_j^2),
//   flip_ij  = (psi_i - psi_j)/(sigma_i - sigma_j) = c0 + mu (s_i^2 + s_i s_j + s_j^2),
//   d2Psi/dsigma_i dsigma_j = delta_ij (c0 + 3 mu s_i^2) + lambda s_i s_j.
template <int Dim>
void project(const md::Mat<Dim>& F, const LameParameters& lame, double trE, md::Tangent<Dim>& T) {
  using Modes = md::IsotropicModes<Dim>;
  md::RotationVariantSvd<Dim> svd;
  md::rotation_variant_svd(F, svd);
  const Eigen::Matrix<double, Dim, 1>& sg = svd.sigma;
  const double c0 = lame.lambda * trE - lame.mu;
  Modes modes;
  for (int p = 0; p < Modes::kPairs; ++p) {
    const double si = sg(Modes::first(p)), sj = sg(Modes::second(p));
    modes.twist(p) = c0 + lame.mu * (si * si - si * sj + sj * sj);
    modes.flip(p) = c0 + lame.mu * (si * si + si * sj + sj * sj);
  }
  modes.scaling.noalias() = lame.lambda * sg * sg.transpose();
  modes.scaling.diagonal().array() += c0 + 3.0 * lame.mu * sg.array().square();
  md::subtract_negative_modes<Dim>(svd, modes, T);
}

}  // namespace

template <int Dim>
void StvkMaterial<Dim>::evaluate(const Mat& F, const LameParameters& lame, bool want_stress,
                                 bool want_tangent, HessianMode mode, MaterialEvaluation<Dim>& out) const {
  const Mat E = 0.5 * (F.transpose() * F - Mat::Identity());
  const double tr = E.trace();
  out.energy_density = 0.5 * lame.lambda * tr * tr + lame.mu * E.squaredNorm();
  if (!want_stress && !want_tangent) return;
  const Mat S = lame.lambda * tr * Mat::Identity() + 2.0 * lame.mu * E;  // second Piola-Kirchhoff
  if (want_stress) out.stress.noalias() = F * S;
  if (want_tangent) {
    const Mat B = F * F.transpose();
    auto& T = out.tangent;
    for (int l = 0; l < Dim; ++l)
      for (int k = 0; k < Dim; ++k)
        for (int j = 0; j < Dim; ++j)
          for (int i = 0; i < Dim; ++i) {
            double v = lame.lambda * F(i, j) * F(k, l) + lame.mu * F(i, l) * F(k, j);
            if (i == k) v += S(l, j);
            if (j == l) v += lame.mu * B(i, k);
            T(i + Dim * j, k + Dim * l) = v;
          }
    if (mode == HessianMode::projected && !cholesky_accepts<Dim * Dim>(T)) project(F, lame, tr, T);
  }
}

template <int Dim>
void StvkMaterial<Dim>::lame_derivatives(const Mat& F, const LameParameters& /*lame*/,
                                         MaterialLameDerivatives<Dim>& out) const {
  const Mat E = 0.5 * (F.transpose() * F - Mat::Identity());
  const double tr = E.trace();
  out.energy_density << 0.5 * tr * tr, E.squaredNorm();
  const Mat dP_dlambda = tr * F;
  const Mat dP_dmu = 2.0 * F * E;
  out.stress.col(0) = md::vec<Dim>(dP_dlambda);
  out.stress.col(1) = md::vec<Dim>(dP_dmu);
}

template class StvkMaterial<2>;
template class StvkMaterial<3>;

// The registry's entry (forward/fem/material_registry.hpp).
MaterialEntry stvk_material_entry() {
  return make_material_entry<StvkMaterial>("stvk",
                                           "Saint Venant-Kirchhoff: linear elasticity on the Green strain",
                                           {.polynomial_in_deformation = true});
}

}  // namespace tailor
