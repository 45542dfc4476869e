#include "forward/fem/materials/spline_material.hpp"

#include <algorithm>
#include <cmath>

#include "forward/fem/materials/isotropic_projection.hpp"
#include "forward/fem/materials/rotation_variant_svd.hpp"
#include "forward/fem/materials/tensor_ops.hpp"

namespace tailor {
namespace md = material_detail;
namespace {

// Pair p of the three stretches: (0,1), (0,2), (1,2) (the order of IsotropicModes), k the third.
constexpr int kPair[3][3] = {{0, 1, 2}, {0, 2, 1}, {1, 2, 0}};

// Psi and its derivatives in the three principal stretches l (l_3 = 1 in plane strain).
struct StretchDerivatives {
  double energy = 0.0;
  Eigen::Vector3d gradient;  // psi_a
  Eigen::Matrix3d hessian;
  Eigen::Vector3d twist, flip;  // per pair
};

// order: 0 energy, 1 + gradient, 2 + Hessian and the pair eigenvalues of the first `pairs` pairs.
void stretch_derivatives(const PrincipalStretchCurves& c, const Eigen::Vector3d& l, int order, int pairs,
                         StretchDerivatives& d) {
  const Eigen::Vector3d others(l[1] * l[2], l[0] * l[2], l[0] * l[1]);  // J / l_a
  const double J = l[0] * l[1] * l[2];
  CubicSpline::Sample f[3], g[3];
  for (int a = 0; a < 3; ++a) f[a] = c.uniaxial.evaluate(l[a]);
  for (int p = 0; p < 3; ++p) g[p] = c.biaxial.evaluate(l[kPair[p][0]] * l[kPair[p][1]]);
  const CubicSpline::Sample h = c.volumetric.evaluate(J);
  d.energy = f[0].value + f[1].value + f[2].value + g[0].value + g[1].value + g[2].value + h.value;
  if (order < 1) return;
  for (int a = 0; a < 3; ++a) d.gradient[a] = f[a].slope + others[a] * h.slope;
  for (int p = 0; p < 3; ++p) {
    const int i = kPair[p][0], j = kPair[p][1];
    d.gradient[i] += l[j] * g[p].slope;
    d.gradient[j] += l[i] * g[p].slope;
  }
  if (order < 2) return;
  for (int a = 0; a < 3; ++a) d.hessian(a, a) = f[a].curvature + others[a] * others[a] * h.curvature;
  for (int p = 0; p < 3; ++p) {
    const int i = kPair[p][0], j = kPair[p][1], k = kPair[p][2];
    const double t = l[i] * l[j];
    d.hessian(i, i) += l[j] * l[j] * g[p].curvature;
    d.hessian(j, j) += l[i] * l[i] * g[p].curvature;
    d.hessian(i, j) = d.hessian(j, i) =
        g[p].slope + t * g[p].curvature + l[k] * h.slope + others[i] * others[j] * h.curvature;
  }
  const double floor = kSplineTwistFloor * std::max(1.0, l[0]);
  for (int p = 0; p < pairs; ++p) {
    const int i = kPair[p][0], j = kPair[p][1], k = kPair[p][2];
    const int ik = i + k - 1, jk = j + k - 1;  // pair indices of (i, k) and (j, k), sorted
    d.flip[p] = c.uniaxial.slope_divided_difference(l[i], l[j]) - g[p].slope +
                l[k] * l[k] * c.biaxial.slope_divided_difference(l[i] * l[k], l[j] * l[k]) - l[k] * h.slope;
    d.twist[p] =
        (f[i].slope + f[j].slope + l[k] * (g[ik].slope + g[jk].slope)) / std::max(l[i] + l[j], floor) +
        g[p].slope + l[k] * h.slope;
  }
}

template <int Dim>
Eigen::Vector3d padded(const Eigen::Matrix<double, Dim, 1>& sigma) {
  if constexpr (Dim == 3) {
    return sigma;
  } else {
    return {sigma[0], sigma[1], 1.0};
  }
}

}  // namespace

template <int Dim>
PrincipalFrame<Dim> principal_frame(const Eigen::Matrix<double, Dim, Dim>& F) {
  md::RotationVariantSvd<Dim> svd;
  md::rotation_variant_svd(F, svd);
  return {svd.U, svd.V, padded<Dim>(svd.sigma)};
}

template <int Dim>
void evaluate_spline_material(const PrincipalStretchCurves& curves, const Eigen::Matrix<double, Dim, Dim>& F,
                              bool want_stress, bool want_tangent, HessianMode mode,
                              MaterialEvaluation<Dim>& out) {
  using Modes = md::IsotropicModes<Dim>;
  md::RotationVariantSvd<Dim> svd;
  md::rotation_variant_svd(F, svd);
  const Eigen::Vector3d l = padded<Dim>(svd.sigma);
  StretchDerivatives d;
  stretch_derivatives(curves, l, want_tangent ? 2 : (want_stress ? 1 : 0), Modes::kPairs, d);
  out.energy_density = d.energy;
  const auto& U = svd.U;
  const auto& V = svd.V;
  if (want_stress) out.stress.noalias() = U * d.gradient.template head<Dim>().asDiagonal() * V.transpose();
  if (!want_tangent) return;

  // T = sum_ab H_ab s_a s_b^T + sum_p (twist_p w_p w_p^T + flip_p q_p q_p^T), s_a = vec(u_a v_a^T),
  // w_p, q_p = vec(u_i v_j^T -+ u_j v_i^T)/sqrt(2).
  Eigen::Matrix<double, Dim * Dim, Dim> S;
  for (int a = 0; a < Dim; ++a) {
    const md::Mat<Dim> A = U.col(a) * V.col(a).transpose();
    S.col(a) = md::vec<Dim>(A);
  }
  const Eigen::Matrix<double, Dim, Dim> H = d.hessian.template topLeftCorner<Dim, Dim>();
  auto& T = out.tangent;
  T.noalias() = S * H * S.transpose();
  for (int p = 0; p < Modes::kPairs; ++p) {
    const int i = kPair[p][0], j = kPair[p][1];
    const md::Mat<Dim> A = U.col(i) * V.col(j).transpose(), B = U.col(j) * V.col(i).transpose();
    const md::Mat<Dim> W = A - B, Q = A + B;
    T.noalias() += (0.5 * d.twist[p]) * md::vec<Dim>(W) * md::vec<Dim>(W).transpose();
    T.noalias() += (0.5 * d.flip[p]) * md::vec<Dim>(Q) * md::vec<Dim>(Q).transpose();
  }
  if (mode != HessianMode::projected) return;
  Modes modes;
  modes.twist = d.twist.template head<Modes::kPairs>();
  modes.flip = d.flip.template head<Modes::kPairs>();
  modes.scaling = H;
  md::subtract_negative_modes<Dim>(svd, modes, T);
}

template <int Dim>
void evaluate_spline_material_modes(const PrincipalStretchCurves& curves,
                                    const Eigen::Matrix<double, Dim, Dim>& F, MaterialEvaluation<Dim>& out,
                                    SplineTangentModes<Dim>& modes) {
  md::RotationVariantSvd<Dim> svd;
  md::rotation_variant_svd(F, svd);
  StretchDerivatives d;
  stretch_derivatives(curves, padded<Dim>(svd.sigma), 2, SplineTangentModes<Dim>::kPairs, d);
  out.energy_density = d.energy;
  out.stress.noalias() = svd.U * d.gradient.template head<Dim>().asDiagonal() * svd.V.transpose();
  modes.U = svd.U;
  modes.V = svd.V;
  modes.stretch_hessian = d.hessian.template topLeftCorner<Dim, Dim>();
  modes.twist = d.twist.template head<SplineTangentModes<Dim>::kPairs>();
  modes.flip = d.flip.template head<SplineTangentModes<Dim>::kPairs>();
}

void add_control_derivatives(const PrincipalStretchCurves& curves, const Eigen::Vector3d& l,
                             double energy_weight, const Eigen::Vector3d& stress_weights,
                             Eigen::Ref<Eigen::VectorXd> out) {
  const int nf = curves.uniaxial.num_controls(), ng = curves.biaxial.num_controls();
  const Eigen::Vector3d others(l[1] * l[2], l[0] * l[2], l[0] * l[1]);
  for (int a = 0; a < 3; ++a) {
    const CubicSpline::Basis b = curves.uniaxial.basis(l[a]);
    out.segment<4>(b.first) += energy_weight * b.value + stress_weights[a] * b.slope;
  }
  for (int p = 0; p < 3; ++p) {
    const int i = kPair[p][0], j = kPair[p][1];
    const CubicSpline::Basis b = curves.biaxial.basis(l[i] * l[j]);
    out.segment<4>(nf + b.first) +=
        energy_weight * b.value + (stress_weights[i] * l[j] + stress_weights[j] * l[i]) * b.slope;
  }
  const CubicSpline::Basis b = curves.volumetric.basis(l[0] * l[1] * l[2]);
  out.segment<4>(nf + ng + b.first) += energy_weight * b.value + stress_weights.dot(others) * b.slope;
}

template <int Dim>
void SplineMaterial<Dim>::evaluate(const Mat& F, const LameParameters& /*lame*/, bool want_stress,
                                   bool want_tangent, HessianMode mode, MaterialEvaluation<Dim>& out) const {
  evaluate_spline_material<Dim>(curves_, F, want_stress, want_tangent, mode, out);
}

template <int Dim>
void SplineMaterial<Dim>::lame_derivatives(const Mat& /*F*/, const LameParameters& /*lame*/,
                                           MaterialLameDerivatives<Dim>& out) const {
  out.energy_density.setZero();
  out.stress.setZero();
}

template void evaluate_spline_material<2>(const PrincipalStretchCurves&, const Eigen::Matrix2d&, bool, bool,
                                          HessianMode, MaterialEvaluation<2>&);
template void evaluate_spline_material<3>(const PrincipalStretchCurves&, const Eigen::Matrix3d&, bool, bool,
                                          HessianMode, MaterialEvaluation<3>&);
template void evaluate_spline_material_modes<2>(const PrincipalStretchCurves&, const Eigen::Matrix2d&,
                                                MaterialEvaluation<2>&, SplineTangentModes<2>&);
template void evaluate_spline_material_modes<3>(const PrincipalStretchCurves&, const Eigen::Matrix3d&,
                                                MaterialEvaluation<3>&, SplineTangentModes<3>&);
template PrincipalFrame<2> principal_frame<2>(const Eigen::Matrix2d&);
template PrincipalFrame<3> principal_frame<3>(const Eigen::Matrix3d&);
template class SplineMaterial<2>;
template class SplineMaterial<3>;

}  // namespace tailor
