#pragma once
// Principal-stretch spline material (Xu, Sin, Zhu, Barbic 2015): the density of
// principal_stretch_curves.hpp evaluated through the rotation-variant SVD F = U diag(l) V^T.
//
//  - Stress (Xu et al. Eq. 7): P = U diag(psi) V^T, psi_a = dPsi/dl_a
//      = f'(l_a) + sum_{b != a} l_b g'(l_a l_b) + (J / l_a) h'(J)   (J / l_a as a product, no division).
//  - Tangent: block diagonal in the SVD basis (isotropic_projection.hpp): the Dim x Dim Hessian
//    d2Psi/dl2 on span vec(u_a v_a^T), and per pair (i, j), k the third index,
//      twist = (psi_i + psi_j)/(l_i + l_j)
//            = (f'(l_i) + f'(l_j) + l_k (g'(l_i l_k) + g'(l_j l_k)))/(l_i + l_j) + g'(l_i l_j) + l_k h'(J),
//      flip  = (psi_i - psi_j)/(l_i - l_j)
//            = D[f'](l_i, l_j) - g'(l_i l_j) + l_k^2 D[g'](l_i l_k, l_j l_k) - l_k h'(J),
//    D[y'](a, b) = (y'(a) - y'(b))/(a - b) taken from the spline structure without cancellation
//    (CubicSpline::slope_divided_difference), so coincident and nearly coincident stretches need
//    no special case and the flip term is exact to round-off. The twist denominator
//    l_i + l_j >= 0 vanishes only for F with l_i = -l_j (inverted, non-differentiable SVD); it is
//    floored at kTwistFloor * max(1, l_0) as in the corotated material.
//  - Projected tangent: the negative twist/flip eigenvalues and the negative eigenvalues of
//    the stretch Hessian are removed (subtract_negative_modes), the exact spectral clamp.
//  - Plane strain: l_3 = 1 pinned (see principal_stretch_curves.hpp); the in-plane modes are
//    those of the 3D formulas with k = 3.
//
// Control-value derivatives: Psi is linear in the control values c = [f; g; h], and so are
// psi_a, so dP/dc = sum_a vec(u_a v_a^T) dpsi_a/dc.
#include <Eigen/Core>

#include "forward/fem/material.hpp"
#include "forward/fem/materials/principal_stretch_curves.hpp"

namespace tailor {

inline constexpr double kSplineTwistFloor = 1e-8;

// Energy density, stress and tangent of the curves at F (units: energy per rest volume).
template <int Dim>
void evaluate_spline_material(const PrincipalStretchCurves& curves, const Eigen::Matrix<double, Dim, Dim>& F,
                              bool want_stress, bool want_tangent, HessianMode mode,
                              MaterialEvaluation<Dim>& out);

// The exact tangent as modes in the SVD basis, for callers that contract it with a linear map
// (an element's B: B^T T B = sum over modes of (B^T m)(B^T m)^T, cheaper than forming T):
//   T = sum_ab stretch_hessian_ab s_a s_b^T + sum_p (twist_p w_p w_p^T + flip_p q_p q_p^T),
//   s_a = vec(u_a v_a^T), w_p, q_p = vec(u_i v_j^T -+ u_j v_i^T) / sqrt(2), pairs (0,1), (0,2), (1,2).
template <int Dim>
struct SplineTangentModes {
  static constexpr int kPairs = Dim == 3 ? 3 : 1;
  Eigen::Matrix<double, Dim, Dim> U, V;
  Eigen::Matrix<double, Dim, Dim> stretch_hessian;
  Eigen::Matrix<double, kPairs, 1> twist, flip;
};
// Energy density and stress into `out` (its tangent untouched) and the exact tangent's modes.
template <int Dim>
void evaluate_spline_material_modes(const PrincipalStretchCurves& curves,
                                    const Eigen::Matrix<double, Dim, Dim>& F, MaterialEvaluation<Dim>& out,
                                    SplineTangentModes<Dim>& modes);

// The principal stretches and frames of F (rotation-variant SVD), as the control derivatives need.
template <int Dim>
struct PrincipalFrame {
  Eigen::Matrix<double, Dim, Dim> U, V;
  Eigen::Vector3d stretches;  // (l_1, l_2, l_3), l_3 = 1 in plane strain
};
template <int Dim>
PrincipalFrame<Dim> principal_frame(const Eigen::Matrix<double, Dim, Dim>& F);

// out += energy_weight dPsi/dc + sum_a stress_weights[a] dpsi_a/dc at the given stretches, for
// the flat control vector c = [f; g; h] (out has curves.num_controls() entries). With
// stress_weights[a] = u_a^T W v_a this is the contraction W : dP/dc.
void add_control_derivatives(const PrincipalStretchCurves& curves, const Eigen::Vector3d& stretches,
                             double energy_weight, const Eigen::Vector3d& stress_weights,
                             Eigen::Ref<Eigen::VectorXd> out);

// A Material<Dim> with fixed curves. The Lame parameters passed by ElasticTerm are ignored
// (the curves carry the moduli; lame_derivatives are zero). Use SplineElasticTerm to make the
// control values design parameters.
template <int Dim>
class SplineMaterial final : public Material<Dim> {
 public:
  using typename Material<Dim>::Mat;
  explicit SplineMaterial(PrincipalStretchCurves curves) : curves_(std::move(curves)) {}
  std::string name() const override { return "spline"; }
  void evaluate(const Mat& F, const LameParameters& lame, bool want_stress, bool want_tangent,
                HessianMode mode, MaterialEvaluation<Dim>& out) const override;
  void lame_derivatives(const Mat& F, const LameParameters& lame,
                        MaterialLameDerivatives<Dim>& out) const override;
  const PrincipalStretchCurves& curves() const { return curves_; }

 private:
  PrincipalStretchCurves curves_;
};

extern template class SplineMaterial<2>;
extern template class SplineMaterial<3>;

}  // namespace tailor
