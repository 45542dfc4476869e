#include "forward/fem/materials/linear.hpp"

#include <algorithm>

#include "forward/fem/material_registry.hpp"
#include "forward/fem/materials/tensor_ops.hpp"

namespace tailor {
namespace md = material_detail;

template <int Dim>
void LinearMaterial<Dim>::evaluate(const Mat& F, const LameParameters& lame, bool want_stress,
                                   bool want_tangent, HessianMode mode, MaterialEvaluation<Dim>& out) const {
  const Mat eps = 0.5 * (F + F.transpose()) - Mat::Identity();
  const double tr = eps.trace();
  out.energy_density = 0.5 * lame.lambda * tr * tr + lame.mu * eps.squaredNorm();
  if (want_stress) out.stress = lame.lambda * tr * Mat::Identity() + 2.0 * lame.mu * eps;
  if (want_tangent) {
    // Spectral form: mu (I + K) = 2 mu Pi_sym, lambda vec(I)vec(I)^T = Dim lambda Pi_trace, with
    // Pi_sym = Pi_dev + Pi_trace. Eigenvalues: 2 mu on Pi_dev, Dim lambda + 2 mu on Pi_trace.
    double shear = lame.mu;
    double trace_mode = Dim * lame.lambda + 2.0 * lame.mu;
    if (mode == HessianMode::projected) {
      shear = std::max(shear, 0.0);
      trace_mode = std::max(trace_mode, 0.0);
    }
    out.tangent.setZero();
    md::add_identity_plus_commutation<Dim>(shear, out.tangent);
    md::add_identity_outer<Dim>((trace_mode - 2.0 * shear) / Dim, out.tangent);
  }
}

template <int Dim>
void LinearMaterial<Dim>::lame_derivatives(const Mat& F, const LameParameters& /*lame*/,
                                           MaterialLameDerivatives<Dim>& out) const {
  const Mat eps = 0.5 * (F + F.transpose()) - Mat::Identity();
  const double tr = eps.trace();
  out.energy_density << 0.5 * tr * tr, eps.squaredNorm();
  const Mat dP_dlambda = tr * Mat::Identity();
  const Mat dP_dmu = 2.0 * eps;
  out.stress.col(0) = md::vec<Dim>(dP_dlambda);
  out.stress.col(1) = md::vec<Dim>(dP_dmu);
}

template class LinearMaterial<2>;
template class LinearMaterial<3>;

// The registry's entry (forward/fem/material_registry.hpp).
MaterialEntry linear_material_entry() {
  return make_material_entry<LinearMaterial>("linear", "linear (small-strain) isotropic elasticity",
                                             {.polynomial_in_deformation = true});
}

}  // namespace tailor
