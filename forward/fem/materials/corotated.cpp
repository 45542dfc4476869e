#include "forward/fem/materials/corotated.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "forward/core/psd_projection.hpp"
#include "forward/fem/material_registry.hpp"
#include "forward/fem/materials/rotation_variant_svd.hpp"
#include "forward/fem/materials/tensor_ops.hpp"

namespace tailor {
namespace md = material_detail;
namespace {

// Everything the corotated formulas need from F: R, c = tr(R^T F) - 3 (of the 3D density), and
// the twist modes w_k = vec(u_i v_j^T - u_j v_i^T) (|w_k|^2 = 2) with their sigma_i + sigma_j.
template <int Dim>
struct Kinematics {
  static constexpr int kTwists = Dim == 3 ? 3 : 1;
  md::Mat<Dim> R;
  double c = 0.0;
  std::array<md::VecN<Dim>, kTwists> twist;
  std::array<double, kTwists> twist_sum;
  double sigma_max = 0.0;
};

void compute_kinematics(const md::Mat<2>& F, bool want_twists, Kinematics<2>& k) {
  double tau = 0.0;
  md::rotation_variant_polar_2d(F, k.R, tau);
  k.c = tau - 2.0;                              // tr(R^T F) + 1 - 3 at diag(F, 1)
  k.sigma_max = std::max(F.norm(), tau / 2.0);  // bound on sigma_0, only used to scale the floor
  if (!want_twists) return;
  // In 2D u_0 v_1^T - u_1 v_0^T = -J U V^T = -J R (J the 90 degree rotation, which commutes
  // with U); the sign does not matter in w w^T.
  md::Mat<2> JR;
  JR << -k.R(1, 0), -k.R(1, 1), k.R(0, 0), k.R(0, 1);
  k.twist[0] = md::vec<2>(JR);
  k.twist_sum[0] = tau;
}

void compute_kinematics(const md::Mat<3>& F, bool want_twists, Kinematics<3>& k) {
  md::RotationVariantSvd<3> svd;
  md::rotation_variant_svd(F, svd);
  k.R.noalias() = svd.U * svd.V.transpose();
  k.c = svd.sigma.sum() - 3.0;
  k.sigma_max = svd.sigma(0);
  if (!want_twists) return;
  constexpr int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int p = 0; p < 3; ++p) {
    const int i = pairs[p][0], j = pairs[p][1];
    const md::Mat<3> W = svd.U.col(i) * svd.V.col(j).transpose() - svd.U.col(j) * svd.V.col(i).transpose();
    k.twist[p] = md::vec<3>(W);
    k.twist_sum[p] = svd.sigma(i) + svd.sigma(j);
  }
}

}  // namespace

template <int Dim>
typename CorotatedMaterial<Dim>::Mat CorotatedMaterial<Dim>::rotation(const Mat& F) {
  Kinematics<Dim> k;
  compute_kinematics(F, false, k);
  return k.R;
}

template <int Dim>
void CorotatedMaterial<Dim>::evaluate(const Mat& F, const LameParameters& lame, bool want_stress,
                                      bool want_tangent, HessianMode mode,
                                      MaterialEvaluation<Dim>& out) const {
  const double lambda = lame.lambda, mu = lame.mu;
  Kinematics<Dim> k;
  compute_kinematics(F, want_tangent, k);
  const Mat D = F - k.R;
  out.energy_density = mu * D.squaredNorm() + 0.5 * lambda * k.c * k.c;
  if (want_stress) out.stress = 2.0 * mu * D + lambda * k.c * k.R;
  if (!want_tangent) return;

  // T = 2 mu I + lambda r r^T + sum_k (lambda c - 2 mu)/(sigma_i + sigma_j) w_k w_k^T, r = vec(R);
  // r and the w_k are mutually orthogonal, |r|^2 = Dim, |w_k|^2 = 2.
  const bool analytic_projection = mode == HessianMode::projected && mu >= 0.0;
  const double floor = kTwistFloor * std::max(1.0, k.sigma_max);
  double trace_coefficient = lambda;
  if (analytic_projection && 2.0 * mu + Dim * lambda < 0.0) trace_coefficient = -2.0 * mu / Dim;
  const auto r = md::vec<Dim>(k.R);
  auto& T = out.tangent;
  T.noalias() = trace_coefficient * r * r.transpose();
  T.diagonal().array() += 2.0 * mu;
  for (int p = 0; p < Kinematics<Dim>::kTwists; ++p) {
    double coefficient = (lambda * k.c - 2.0 * mu) / std::max(k.twist_sum[p], floor);
    // Eigenvalue on w/sqrt(2) is 2 mu + 2 coefficient; clamping it to 0 means coefficient = -mu.
    if (analytic_projection) coefficient = std::max(coefficient, -mu);
    T.noalias() += coefficient * k.twist[p] * k.twist[p].transpose();
  }
  // Negative shear modulus (unphysical): every other mode may be negative too, clamp generically.
  if (mode == HessianMode::projected && !analytic_projection) project_psd<Dim * Dim>(T);
}

template <int Dim>
void CorotatedMaterial<Dim>::lame_derivatives(const Mat& F, const LameParameters& /*lame*/,
                                              MaterialLameDerivatives<Dim>& out) const {
  Kinematics<Dim> k;
  compute_kinematics(F, false, k);
  const Mat D = F - k.R;
  out.energy_density << 0.5 * k.c * k.c, D.squaredNorm();
  const Mat dP_dlambda = k.c * k.R;
  const Mat dP_dmu = 2.0 * D;
  out.stress.col(0) = md::vec<Dim>(dP_dlambda);
  out.stress.col(1) = md::vec<Dim>(dP_dmu);
}

template class CorotatedMaterial<2>;
template class CorotatedMaterial<3>;

// The registry's entry (forward/fem/material_registry.hpp).
MaterialEntry corotated_material_entry() {
  return make_material_entry<CorotatedMaterial>(
      "corotated", "linear corotated elasticity (polar decomposition, inversion-safe SVD)",
      {.polynomial_in_deformation = false});
}

}  // namespace tailor
