#include "forward/fem/spline_elastic_term.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "forward/fem/element_loop.hpp"
#include "forward/fem/materials/spline_material.hpp"

namespace tailor {
namespace {

// Element Hessian V B^T T B from the tangent's modes without forming T: B^T vec(M) = vec(M G^T)
// for the element's shape gradients G (rows grad N_a), so a mode u v^T maps to u (G v)^T.
template <int Dim, int Local>
void modal_element_hessian(const SplineTangentModes<Dim>& modes, const Eigen::Matrix<double, Dim + 1, Dim>& G,
                           double volume, typename ElementOutput<Dim>::LocalHessian H) {
  constexpr int kPairs = SplineTangentModes<Dim>::kPairs;
  constexpr int kModes = Dim + 2 * kPairs;
  constexpr int kPair[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  const Eigen::Matrix<double, Dim + 1, Dim> GV = G * modes.V;  // column a: G v_a
  Eigen::Matrix<double, Local, kModes> M;                      // B^T of every mode
  const auto mode = [&](int a, int b) {                        // vec(u_a (G v_b)^T)
    const Eigen::Matrix<double, Dim, Dim + 1> outer = modes.U.col(a) * GV.col(b).transpose();
    return Eigen::Map<const Eigen::Matrix<double, Local, 1>>(outer.data()).eval();
  };
  for (int a = 0; a < Dim; ++a) M.col(a) = mode(a, a);
  const double r = std::sqrt(0.5);
  for (int p = 0; p < kPairs; ++p) {
    const auto A = mode(kPair[p][0], kPair[p][1]), B = mode(kPair[p][1], kPair[p][0]);
    M.col(Dim + p) = r * (A - B);
    M.col(Dim + kPairs + p) = r * (A + B);
  }
  Eigen::Matrix<double, Local, kModes> MD;  // M times the block-diagonal mode matrix and the volume
  MD.template leftCols<Dim>().noalias() = volume * (M.template leftCols<Dim>() * modes.stretch_hessian);
  for (int p = 0; p < kPairs; ++p) {
    MD.col(Dim + p) = (volume * modes.twist[p]) * M.col(Dim + p);
    MD.col(Dim + kPairs + p) = (volume * modes.flip[p]) * M.col(Dim + kPairs + p);
  }
  H.noalias() = MD * M.transpose();
}

}  // namespace

template <int Dim>
SplineElasticTerm<Dim>::SplineElasticTerm(const Mesh& mesh, PrincipalStretchCurves knots, int control_offset,
                                          std::vector<int> elements)
    : knots_(std::move(knots)),
      control_offset_(control_offset),
      simplices_(mesh, std::move(elements), "SplineElasticTerm") {
  if (control_offset < 0)
    throw std::invalid_argument("SplineElasticTerm: negative control offset " +
                                std::to_string(control_offset));
}

template <int Dim>
PrincipalStretchCurves SplineElasticTerm<Dim>::curves(const Vector& p) const {
  if (p.size() < control_offset_ + num_controls())
    throw std::invalid_argument("SplineElasticTerm: the parameter vector has " + std::to_string(p.size()) +
                                " entries, the control block needs " +
                                std::to_string(control_offset_ + num_controls()));
  PrincipalStretchCurves c = knots_;
  c.set_controls(p.segment(control_offset_, num_controls()));
  return c;
}

template <int Dim>
void SplineElasticTerm<Dim>::evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const {
  const PrincipalStretchCurves c = curves(p);
  evaluate_elements<Dim>(simplices_, request, [&](int k, ElementOutput<Dim>& out) {
    MaterialEvaluation<Dim> m;
    const double V = simplices_.volumes[k];
    const auto& G = simplices_.gradients[k];
    // Exact Hessians contract the tangent's modes with B directly (about half the flops of
    // forming T and B^T T B); projected ones clamp T in the material.
    if (out.want_hessian && out.hessian_mode == HessianMode::exact) {
      SplineTangentModes<Dim> modes;
      evaluate_spline_material_modes<Dim>(c, simplices_.field_gradient(x, k), m, modes);
      modal_element_hessian<Dim, kLocal>(modes, G, V, out.hessian());
    } else {
      evaluate_spline_material<Dim>(c, simplices_.field_gradient(x, k), out.want_gradient, out.want_hessian,
                                    out.hessian_mode, m);
      if (out.want_hessian) {
        const auto B = LinearSimplices<Dim>::deformation_jacobian(G);
        // Coefficient-based products (see elastic_term.cpp).
        out.hessian().noalias() = V * B.transpose().lazyProduct(m.tangent.lazyProduct(B));
      }
    }
    out.energy = V * m.energy_density;
    if (out.want_gradient)  // f_a = V P grad N_a
      out.gradient().noalias() = V * m.stress * G.transpose();
  });
}

template <int Dim>
void SplineElasticTerm<Dim>::hessian_pattern(HessianPattern& pattern) const {
  simplices_.append_hessian_pattern(pattern);
}

template <int Dim>
void SplineElasticTerm<Dim>::add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const {
  const PrincipalStretchCurves c = curves(p);
  auto block = gradient_p.segment(control_offset_, num_controls());
  for (int k = 0; k < simplices_.size(); ++k) {
    const auto frame = principal_frame<Dim>(simplices_.field_gradient(x, k));
    add_control_derivatives(c, frame.stretches, simplices_.volumes[k], Eigen::Vector3d::Zero(), block);
  }
}

template <int Dim>
void SplineElasticTerm<Dim>::add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const {
  const PrincipalStretchCurves c = curves(p);
  Eigen::VectorXd column(num_controls());
  for (int k = 0; k < simplices_.size(); ++k) {
    const auto frame = principal_frame<Dim>(simplices_.field_gradient(x, k));
    // d f_local / d psi_a = V B^T vec(u_a v_a^T)
    Eigen::Matrix<double, Dim * Dim, Dim> S;
    for (int a = 0; a < Dim; ++a) {
      const Eigen::Matrix<double, Dim, Dim> A = frame.U.col(a) * frame.V.col(a).transpose();
      S.col(a) = Eigen::Map<const Eigen::Matrix<double, Dim * Dim, 1>>(A.data());
    }
    const Eigen::Matrix<double, kLocal, Dim> weights =
        simplices_.volumes[k] *
        LinearSimplices<Dim>::deformation_jacobian(simplices_.gradients[k]).transpose() * S;
    for (int r = 0; r < kLocal; ++r) {
      Eigen::Vector3d w = Eigen::Vector3d::Zero();
      w.head<Dim>() = weights.row(r).transpose();
      column.setZero();
      add_control_derivatives(c, frame.stretches, 0.0, w, column);
      for (int j = 0; j < num_controls(); ++j)
        if (column[j] != 0.0) mixed.emplace_back(simplices_.dof(k, r), control_offset_ + j, column[j]);
    }
  }
}

template <int Dim>
void SplineElasticTerm<Dim>::add_mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w,
                                                       Vector& gradient_p) const {
  const PrincipalStretchCurves c = curves(p);
  auto block = gradient_p.segment(control_offset_, num_controls());
  for (int k = 0; k < simplices_.size(); ++k) {
    const auto frame = principal_frame<Dim>(simplices_.field_gradient(x, k));
    // W : dP/dc = sum_a (u_a^T W v_a) dpsi_a/dc, W = grad of w on the element.
    const Eigen::Matrix<double, Dim, Dim> W = simplices_.field_gradient(w, k);
    Eigen::Vector3d weights = Eigen::Vector3d::Zero();
    for (int a = 0; a < Dim; ++a) weights[a] = simplices_.volumes[k] * frame.U.col(a).dot(W * frame.V.col(a));
    add_control_derivatives(c, frame.stretches, 0.0, weights, block);
  }
}

template class SplineElasticTerm<2>;
template class SplineElasticTerm<3>;

}  // namespace tailor
