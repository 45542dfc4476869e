#include "forward/fem/elastic_term.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <stdexcept>
#include <string>

namespace tailor {
namespace {

// dvec(F)/dx_local for shape gradients G: entry (i + Dim*j, Dim*a + k) = delta_ik G(a, j).
template <int Dim>
Eigen::Matrix<double, Dim * Dim, Dim*(Dim + 1)> deformation_jacobian(
    const Eigen::Matrix<double, Dim + 1, Dim>& G) {
  Eigen::Matrix<double, Dim * Dim, Dim*(Dim + 1)> B = Eigen::Matrix<double, Dim * Dim, Dim*(Dim + 1)>::Zero();
  for (int a = 0; a <= Dim; ++a)
    for (int j = 0; j < Dim; ++j)
      for (int i = 0; i < Dim; ++i) B(i + Dim * j, Dim * a + i) = G(a, j);
  return B;
}

}  // namespace

template <int Dim>
ElasticTerm<Dim>::ElasticTerm(const Mesh& mesh, std::shared_ptr<const Material<Dim>> material,
                              int youngs_offset, int poisson_offset, std::vector<int> elements)
    : material_(std::move(material)),
      youngs_offset_(youngs_offset),
      poisson_offset_(poisson_offset),
      elements_(std::move(elements)) {
  if (mesh.dim() != Dim || mesh.elements.cols() != kNodes)
    throw std::invalid_argument("ElasticTerm<" + std::to_string(Dim) + ">: the mesh has dimension " +
                                std::to_string(mesh.dim()));
  if (!material_) throw std::invalid_argument("ElasticTerm: no material given");
  if (elements_.empty()) {
    elements_.resize(mesh.num_elements());
    for (int e = 0; e < mesh.num_elements(); ++e) elements_[e] = e;
  }
  {
    std::vector<int> sorted = elements_;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
      throw std::invalid_argument("ElasticTerm: element " + std::to_string(*std::adjacent_find(sorted.begin(), sorted.end())) +
                                  " is listed twice");
  }
  vertices_.resize(elements_.size());
  gradients_.resize(elements_.size());
  volumes_.resize(elements_.size());
  for (std::size_t k = 0; k < elements_.size(); ++k) {
    const int e = elements_[k];
    if (e < 0 || e >= mesh.num_elements())
      throw std::invalid_argument("ElasticTerm: element index " + std::to_string(e) + " out of range");
    Eigen::Matrix<double, Dim, Dim> Dm;
    for (int a = 0; a < Dim; ++a)
      Dm.col(a) = (mesh.rest_positions.row(mesh.elements(e, a + 1)) - mesh.rest_positions.row(mesh.elements(e, 0))).transpose();
    const double det = Dm.determinant();
    if (!(det > 0.0))
      throw std::invalid_argument("ElasticTerm: element " + std::to_string(e) +
                                  " is degenerate or inverted at rest (signed measure " + std::to_string(det) + ")");
    const Eigen::Matrix<double, Dim, Dim> Dm_inv = Dm.inverse();
    ShapeGradients G;
    G.template bottomRows<Dim>() = Dm_inv;  // grad N_a = row a-1 of Dm^{-1}
    G.row(0) = -Dm_inv.colwise().sum();
    gradients_[k] = G;
    volumes_[k] = det / (Dim == 3 ? 6.0 : 2.0);
    for (int a = 0; a < kNodes; ++a) vertices_[k][a] = mesh.elements(e, a);
  }
}

template <int Dim>
LameParameters ElasticTerm<Dim>::lame(const Vector& p, int element) const {
  return lame_from_young_poisson(p[youngs_offset_ + element], p[poisson_offset_ + element]);
}

template <int Dim>
Eigen::Matrix<double, Dim, Dim> ElasticTerm<Dim>::deformation_gradient(const Vector& x, int k) const {
  Eigen::Matrix<double, Dim, Dim> F = Eigen::Matrix<double, Dim, Dim>::Zero();
  for (int a = 0; a < kNodes; ++a)
    F.noalias() += x.template segment<Dim>(Dim * vertices_[k][a]) * gradients_[k].row(a);
  return F;
}

template <int Dim>
void ElasticTerm<Dim>::evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const {
  const auto num = static_cast<std::ptrdiff_t>(elements_.size());
  const bool want_stress = request.gradient != nullptr;
  const bool want_tangent = request.hessian_values != nullptr;
  if (want_stress) local_gradients_.resize(elements_.size() * kLocal);
  double energy = 0.0;
  constexpr int kSlots = kLocal * kLocal;

#pragma omp parallel for schedule(static) reduction(+ : energy) if (num > 256)
  for (std::ptrdiff_t k = 0; k < num; ++k) {
    const auto F = deformation_gradient(x, static_cast<int>(k));
    MaterialEvaluation<Dim> m;
    material_->evaluate(F, lame(p, elements_[k]), want_stress, want_tangent, request.hessian_mode, m);
    const double V = volumes_[k];
    energy += V * m.energy_density;
    const ShapeGradients& G = gradients_[k];
    if (want_stress) {
      // f_a = V P grad N_a
      const Eigen::Matrix<double, Dim, kNodes> local = V * m.stress * G.transpose();
      std::copy(local.data(), local.data() + kLocal, local_gradients_.data() + k * kLocal);
    }
    if (want_tangent) {
      const auto B = deformation_jacobian<Dim>(G);
      const Eigen::Matrix<double, kLocal, kLocal> H = V * (B.transpose() * m.tangent * B);
      // Row-major slots match hessian_pattern(); H is symmetric so column-major storage is
      // the same sequence.
      std::copy(H.data(), H.data() + kSlots, request.hessian_values + k * kSlots);
    }
  }
  if (request.value) *request.value += energy;
  if (want_stress) {
    Vector& g = *request.gradient;
    for (std::size_t k = 0; k < elements_.size(); ++k)
      for (int a = 0; a < kNodes; ++a)
        g.template segment<Dim>(Dim * vertices_[k][a]) +=
            Eigen::Map<const Eigen::Matrix<double, Dim, 1>>(local_gradients_.data() + k * kLocal + Dim * a);
  }
}

template <int Dim>
void ElasticTerm<Dim>::hessian_pattern(HessianPattern& pattern) const {
  pattern.reserve(pattern.size() + elements_.size() * kLocal * kLocal);
  for (std::size_t k = 0; k < elements_.size(); ++k)
    for (int r = 0; r < kLocal; ++r)
      for (int c = 0; c < kLocal; ++c)
        pattern.push_back({Dim * vertices_[k][r / Dim] + r % Dim, Dim * vertices_[k][c / Dim] + c % Dim});
}

template <int Dim>
void ElasticTerm<Dim>::add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const {
  for (std::size_t k = 0; k < elements_.size(); ++k) {
    const int e = elements_[k];
    MaterialLameDerivatives<Dim> d;
    material_->lame_derivatives(deformation_gradient(x, static_cast<int>(k)), lame(p, e), d);
    // dPsi/d(E, nu) = dPsi/d(lambda, mu) * d(lambda, mu)/d(E, nu)
    const Eigen::RowVector2d dpsi = d.energy_density.transpose() * lame_jacobian(p[youngs_offset_ + e], p[poisson_offset_ + e]);
    gradient_p[youngs_offset_ + e] += volumes_[k] * dpsi[0];
    gradient_p[poisson_offset_ + e] += volumes_[k] * dpsi[1];
  }
}

template <int Dim>
void ElasticTerm<Dim>::add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const {
  for (std::size_t k = 0; k < elements_.size(); ++k) {
    const int e = elements_[k];
    MaterialLameDerivatives<Dim> d;
    material_->lame_derivatives(deformation_gradient(x, static_cast<int>(k)), lame(p, e), d);
    const Eigen::Matrix<double, Dim * Dim, 2> dP = d.stress * lame_jacobian(p[youngs_offset_ + e], p[poisson_offset_ + e]);
    const auto B = deformation_jacobian<Dim>(gradients_[k]);
    const Eigen::Matrix<double, kLocal, 2> local = volumes_[k] * (B.transpose() * dP);
    for (int r = 0; r < kLocal; ++r) {
      const int dof = Dim * vertices_[k][r / Dim] + r % Dim;
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
  const auto num = static_cast<std::ptrdiff_t>(elements_.size());
#pragma omp parallel for schedule(static) if (num > 256)
  for (std::ptrdiff_t k = 0; k < num; ++k) {
    const int e = elements_[k];
    MaterialLameDerivatives<Dim> d;
    material_->lame_derivatives(deformation_gradient(x, static_cast<int>(k)), lame(p, e), d);
    // w restricted to the element, contracted with dvec(F)/dx: dF = sum_a w_a grad N_a^T.
    Eigen::Matrix<double, Dim, Dim> W = Eigen::Matrix<double, Dim, Dim>::Zero();
    for (int a = 0; a < kNodes; ++a)
      W.noalias() += w.template segment<Dim>(Dim * vertices_[k][a]) * gradients_[k].row(a);
    const Eigen::Map<const Eigen::Matrix<double, Dim * Dim, 1>> w_vec(W.data());
    const Eigen::RowVector2d dlame = volumes_[k] * (w_vec.transpose() * d.stress);
    const Eigen::RowVector2d dyoung_poisson = dlame * lame_jacobian(p[youngs_offset_ + e], p[poisson_offset_ + e]);
    gradient_p[youngs_offset_ + e] += dyoung_poisson[0];
    gradient_p[poisson_offset_ + e] += dyoung_poisson[1];
  }
}

template <int Dim>
Eigen::MatrixXd ElasticTerm<Dim>::stresses(const Vector& x, const Vector& p) const {
  Eigen::MatrixXd out(elements_.size(), Dim * Dim);
  for (std::size_t k = 0; k < elements_.size(); ++k) {
    MaterialEvaluation<Dim> m;
    material_->evaluate(deformation_gradient(x, static_cast<int>(k)), lame(p, elements_[k]), true, false,
                        HessianMode::exact, m);
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) out(k, Dim * i + j) = m.stress(i, j);
  }
  return out;
}

template class ElasticTerm<2>;
template class ElasticTerm<3>;

}  // namespace tailor
