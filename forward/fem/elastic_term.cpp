#include "forward/fem/elastic_term.hpp"

#include "forward/fem/element_loop.hpp"
#include "forward/fem/nodal_kinematics.hpp"

#include <array>
#include <stdexcept>
#include <string>

namespace tailor {

template <int Dim>
ElasticTerm<Dim>::ElasticTerm(const Mesh& mesh, std::shared_ptr<const Material<Dim>> material,
                              int youngs_offset, int poisson_offset, std::vector<int> elements)
    : material_(std::move(material)),
      youngs_offset_(youngs_offset),
      poisson_offset_(poisson_offset),
      simplices_(mesh, std::move(elements), "ElasticTerm") {
  if (!material_) throw std::invalid_argument("ElasticTerm: no material given");
  closed_form_hessian_ = material_->has_simplex_hessian();
}

template <int Dim>
ElasticTerm<Dim>::ElasticTerm(std::shared_ptr<const Material<Dim>> material, int youngs_offset,
                              int poisson_offset, LinearSimplices<Dim> simplices)
    : material_(std::move(material)),
      closed_form_hessian_(material_->has_simplex_hessian()),
      youngs_offset_(youngs_offset),
      poisson_offset_(poisson_offset),
      simplices_(std::move(simplices)) {}

template <int Dim>
bool ElasticTerm<Dim>::share_by_elements(const std::function<bool(const int* dofs, int count)>& keep,
                                         std::unique_ptr<EnergyTerm>& share) const {
  const std::vector<int> kept = elements_kept(simplices_, keep);
  share.reset();
  if (!kept.empty())
    share.reset(new ElasticTerm(material_, youngs_offset_, poisson_offset_, simplices_.subset(kept)));
  return true;
}

template <int Dim>
LameParameters ElasticTerm<Dim>::lame(const Vector& p, int element) const {
  return lame_from_young_poisson(p[youngs_offset_ + element], p[poisson_offset_ + element]);
}

template <int Dim>
Eigen::Matrix<double, Dim, Dim> ElasticTerm<Dim>::deformation_gradient(const Vector& x, int k) const {
  return simplices_.field_gradient(x, k);
}

template <int Dim>
void ElasticTerm<Dim>::evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const {
  evaluate_elements<Dim>(simplices_, request, [&](int k, ElementOutput<Dim>& out) {
    MaterialEvaluation<Dim> m;
    const Eigen::Matrix<double, Dim, Dim> F = deformation_gradient(x, k);
    const LameParameters lame_k = lame(p, simplices_.elements[k]);
    // The exact Hessian in closed form where the material has one; T is not formed then.
    const bool closed_form = out.want_hessian && out.hessian_mode == HessianMode::exact && closed_form_hessian_;
    material_->evaluate(F, lame_k, out.want_gradient, out.want_hessian && !closed_form, out.hessian_mode, m);
    const double V = simplices_.volumes[k];
    const ShapeGradients& G = simplices_.gradients[k];
    out.energy = V * m.energy_density;
    // f_a = V P grad N_a (column a of the Dim x kNodes block, node-major like the local DOFs)
    if (out.want_gradient) out.gradient().noalias() = V * m.stress * G.transpose();
    if (closed_form) {
      material_->simplex_hessian(F, lame_k, G, V, out.hessian_slots);
    } else if (out.want_hessian) {
      const auto B = LinearSimplices<Dim>::deformation_jacobian(G);
      // Coefficient-based products: Eigen sends a fixed 12x9 * 9x9 * 9x12 product through its
      // blocked GEMM path otherwise, about 1.5x slower at this size.
      out.hessian().noalias() = V * B.transpose().lazyProduct(m.tangent.lazyProduct(B));
    }
  });
}

template <int Dim>
void ElasticTerm<Dim>::hessian_pattern(HessianPattern& pattern) const {
  simplices_.append_hessian_pattern(pattern);
}

template <int Dim>
void ElasticTerm<Dim>::add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const {
  for (std::size_t k = 0; k < simplices_.elements.size(); ++k) {
    const int e = simplices_.elements[k];
    MaterialLameDerivatives<Dim> d;
    material_->lame_derivatives(deformation_gradient(x, static_cast<int>(k)), lame(p, e), d);
    // dPsi/d(E, nu) = dPsi/d(lambda, mu) * d(lambda, mu)/d(E, nu)
    const Eigen::RowVector2d dpsi =
        d.energy_density.transpose() * lame_jacobian(p[youngs_offset_ + e], p[poisson_offset_ + e]);
    gradient_p[youngs_offset_ + e] += simplices_.volumes[k] * dpsi[0];
    gradient_p[poisson_offset_ + e] += simplices_.volumes[k] * dpsi[1];
  }
}

template <int Dim>
void ElasticTerm<Dim>::add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const {
  for (std::size_t k = 0; k < simplices_.elements.size(); ++k) {
    const int e = simplices_.elements[k];
    MaterialLameDerivatives<Dim> d;
    material_->lame_derivatives(deformation_gradient(x, static_cast<int>(k)), lame(p, e), d);
    const Eigen::Matrix<double, Dim * Dim, 2> dP =
        d.stress * lame_jacobian(p[youngs_offset_ + e], p[poisson_offset_ + e]);
    const auto B = LinearSimplices<Dim>::deformation_jacobian(simplices_.gradients[k]);
    const Eigen::Matrix<double, kLocal, 2> local = simplices_.volumes[k] * B.transpose().lazyProduct(dP);
    for (int r = 0; r < kLocal; ++r) {
      const int dof = simplices_.dof(static_cast<int>(k), r);
      mixed.emplace_back(dof, youngs_offset_ + e, local(r, 0));
      mixed.emplace_back(dof, poisson_offset_ + e, local(r, 1));
    }
  }
}

template <int Dim>
void ElasticTerm<Dim>::add_mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w,
                                                 Vector& gradient_p) const {
  // Each element writes only its own two parameters, so the loop is race-free as long as no
  // element is covered twice (the constructor's element list has no duplicates by contract).
  const auto num = static_cast<std::ptrdiff_t>(simplices_.elements.size());
  FirstError errors;
#pragma omp parallel for schedule(static) if (num > 256)
  for (std::ptrdiff_t k = 0; k < num; ++k) try {
    const int e = simplices_.elements[k];
    MaterialLameDerivatives<Dim> d;
    material_->lame_derivatives(deformation_gradient(x, static_cast<int>(k)), lame(p, e), d);
    // w restricted to the element, contracted with dvec(F)/dx: dF = sum_a w_a grad N_a^T.
    const Eigen::Matrix<double, Dim, Dim> W = simplices_.field_gradient(w, static_cast<int>(k));
    const Eigen::Map<const Eigen::Matrix<double, Dim * Dim, 1>> w_vec(W.data());
    const Eigen::RowVector2d dlame = simplices_.volumes[k] * (w_vec.transpose() * d.stress);
    const Eigen::RowVector2d dyoung_poisson =
        dlame * lame_jacobian(p[youngs_offset_ + e], p[poisson_offset_ + e]);
    gradient_p[youngs_offset_ + e] += dyoung_poisson[0];
    gradient_p[poisson_offset_ + e] += dyoung_poisson[1];
  } catch (...) {
    errors.capture(k);
  }
  errors.rethrow();
}

template <int Dim>
Eigen::MatrixXd ElasticTerm<Dim>::stresses(const Vector& x, const Vector& p) const {
  Eigen::MatrixXd out(simplices_.elements.size(), Dim * Dim);
  for (std::size_t k = 0; k < simplices_.elements.size(); ++k) {
    MaterialEvaluation<Dim> m;
    material_->evaluate(deformation_gradient(x, static_cast<int>(k)), lame(p, simplices_.elements[k]), true,
                        false, HessianMode::exact, m);
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) out(k, Dim * i + j) = m.stress(i, j);
  }
  return out;
}

template class ElasticTerm<2>;
template class ElasticTerm<3>;

}  // namespace tailor
