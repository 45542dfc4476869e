#include "forward/fem/quadratic_elastic_term.hpp"

#include <array>
#include <stdexcept>
#include <string>

#include "forward/core/parallel_errors.hpp"
#include "forward/fem/element_loop.hpp"
#include "forward/fem/nodal_kinematics.hpp"

namespace tailor {

template <int Dim>
QuadraticElasticTerm<Dim>::QuadraticElasticTerm(const QuadraticMesh& mesh, std::shared_ptr<const Material<Dim>> material,
                                                int youngs_offset, int poisson_offset, std::vector<int> elements)
    : material_(std::move(material)),
      youngs_offset_(youngs_offset),
      poisson_offset_(poisson_offset),
      simplices_(mesh, std::move(elements), "QuadraticElasticTerm") {
  if (!material_) throw std::invalid_argument("QuadraticElasticTerm: no material given");
}

template <int Dim>
QuadraticElasticTerm<Dim>::QuadraticElasticTerm(std::shared_ptr<const Material<Dim>> material, int youngs_offset,
                                                int poisson_offset, QuadraticSimplices<Dim> simplices)
    : material_(std::move(material)),
      youngs_offset_(youngs_offset),
      poisson_offset_(poisson_offset),
      simplices_(std::move(simplices)) {}

template <int Dim>
bool QuadraticElasticTerm<Dim>::share_by_elements(const std::function<bool(const int* dofs, int count)>& keep,
                                                  std::unique_ptr<EnergyTerm>& share) const {
  const std::vector<int> kept = elements_kept(simplices_, keep);
  share.reset();
  if (!kept.empty())
    share.reset(new QuadraticElasticTerm(material_, youngs_offset_, poisson_offset_, simplices_.subset(kept)));
  return true;
}

template <int Dim>
LameParameters QuadraticElasticTerm<Dim>::lame(const Vector& p, int element) const {
  return lame_from_young_poisson(p[youngs_offset_ + element], p[poisson_offset_ + element]);
}

template <int Dim>
Eigen::Matrix2d QuadraticElasticTerm<Dim>::lame_chain(const Vector& p, int element) const {
  return lame_jacobian(p[youngs_offset_ + element], p[poisson_offset_ + element]);
}

template <int Dim>
Eigen::MatrixXd QuadraticElasticTerm<Dim>::stresses(const Vector& x, const Vector& p) const {
  Eigen::MatrixXd out(simplices_.elements.size(), Dim * Dim);
  for (std::size_t k = 0; k < simplices_.elements.size(); ++k) {
    const int kk = static_cast<int>(k);
    const LameParameters lame_k = lame(p, simplices_.elements[k]);
    Eigen::Matrix<double, Dim, Dim> mean = Eigen::Matrix<double, Dim, Dim>::Zero();
    double volume = 0.0;
    for (int q = 0; q < kPoints; ++q) {
      MaterialEvaluation<Dim> m;
      material_->evaluate(deformation_gradient(x, kk, q), lame_k, true, false, HessianMode::exact, m);
      mean += simplices_.weight(kk, q) * m.stress;
      volume += simplices_.weight(kk, q);
    }
    mean /= volume;
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) out(kk, Dim * i + j) = mean(i, j);
  }
  return out;
}

template <int Dim>
void QuadraticElasticTerm<Dim>::evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const {
  evaluate_elements<Dim>(simplices_, request, [&](int k, ElementOutput<Dim, kNodes>& out) {
    const LameParameters lame_k = lame(p, simplices_.elements[static_cast<std::size_t>(k)]);
    out.energy = 0.0;
    if (out.want_gradient) out.gradient().setZero();
    if (out.want_hessian) out.hessian().setZero();
    for (int q = 0; q < kPoints; ++q) {
      MaterialEvaluation<Dim> m;
      material_->evaluate(deformation_gradient(x, k, q), lame_k, out.want_gradient, out.want_hessian,
                          out.hessian_mode, m);
      const double w = simplices_.weight(k, q);
      const auto& G = simplices_.shape_gradients(k, q);
      out.energy += w * m.energy_density;
      // f_a += w P grad N_a (column a, node-major like the local DOFs)
      if (out.want_gradient) out.gradient().noalias() += w * m.stress * G.transpose();
      if (out.want_hessian) {
        // A sum of w B^T T B: positive semidefinite when every T is (the projected mode).
        const auto B = QuadraticSimplices<Dim>::deformation_jacobian(G);
        out.hessian().noalias() += w * B.transpose().lazyProduct(m.tangent.lazyProduct(B));
      }
    }
  });
}

template <int Dim>
void QuadraticElasticTerm<Dim>::hessian_pattern(HessianPattern& pattern) const {
  simplices_.append_hessian_pattern(pattern);
}

template <int Dim>
void QuadraticElasticTerm<Dim>::add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const {
  for (int k = 0; k < simplices_.size(); ++k) {
    const int e = simplices_.elements[static_cast<std::size_t>(k)];
    Eigen::Vector2d dlame = Eigen::Vector2d::Zero();  // dE_e / d(lambda, mu)
    for (int q = 0; q < kPoints; ++q) {
      MaterialLameDerivatives<Dim> d;
      material_->lame_derivatives(deformation_gradient(x, k, q), lame(p, e), d);
      dlame += simplices_.weight(k, q) * d.energy_density;
    }
    const Eigen::RowVector2d dyoung_poisson = dlame.transpose() * lame_chain(p, e);
    gradient_p[youngs_offset_ + e] += dyoung_poisson[0];
    gradient_p[poisson_offset_ + e] += dyoung_poisson[1];
  }
}

template <int Dim>
void QuadraticElasticTerm<Dim>::add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const {
  for (int k = 0; k < simplices_.size(); ++k) {
    const int e = simplices_.elements[static_cast<std::size_t>(k)];
    const Eigen::Matrix2d chain = lame_chain(p, e);
    Eigen::Matrix<double, kLocal, 2> local = Eigen::Matrix<double, kLocal, 2>::Zero();
    for (int q = 0; q < kPoints; ++q) {
      MaterialLameDerivatives<Dim> d;
      material_->lame_derivatives(deformation_gradient(x, k, q), lame(p, e), d);
      const Eigen::Matrix<double, Dim * Dim, 2> dP = d.stress * chain;
      const auto B = QuadraticSimplices<Dim>::deformation_jacobian(simplices_.shape_gradients(k, q));
      local.noalias() += simplices_.weight(k, q) * B.transpose().lazyProduct(dP);
    }
    for (int r = 0; r < kLocal; ++r) {
      const int dof = simplices_.dof(k, r);
      mixed.emplace_back(dof, youngs_offset_ + e, local(r, 0));
      mixed.emplace_back(dof, poisson_offset_ + e, local(r, 1));
    }
  }
}

template <int Dim>
void QuadraticElasticTerm<Dim>::add_mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w,
                                                          Vector& gradient_p) const {
  // Each element writes only its own two parameters (no element is covered twice), so the
  // parallel loop is race-free and its result independent of the thread count.
  const int num = simplices_.size();
  FirstError errors;
#pragma omp parallel for schedule(static) if (num > 256)
  for (int k = 0; k < num; ++k) try {
    const int e = simplices_.elements[static_cast<std::size_t>(k)];
    Eigen::RowVector2d dlame = Eigen::RowVector2d::Zero();
    for (int q = 0; q < kPoints; ++q) {
      MaterialLameDerivatives<Dim> d;
      material_->lame_derivatives(deformation_gradient(x, k, q), lame(p, e), d);
      // w restricted to the element, contracted with dvec(F_q)/dx: dF = sum_a w_a grad N_a^T.
      const Eigen::Matrix<double, Dim, Dim> W = simplices_.field_gradient(w, k, q);
      const Eigen::Map<const Eigen::Matrix<double, Dim * Dim, 1>> w_vec(W.data());
      dlame += simplices_.weight(k, q) * (w_vec.transpose() * d.stress);
    }
    const Eigen::RowVector2d dyoung_poisson = dlame * lame_chain(p, e);
    gradient_p[youngs_offset_ + e] += dyoung_poisson[0];
    gradient_p[poisson_offset_ + e] += dyoung_poisson[1];
  } catch (...) {
    errors.capture(k);
  }
  errors.rethrow();
}

template class QuadraticElasticTerm<2>;
template class QuadraticElasticTerm<3>;

}  // namespace tailor
