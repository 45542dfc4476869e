#include "forward/reduction/subspace_elements.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "forward/fem/elastic_term.hpp"

namespace tailor {

// One element; exactly one of the material pointers is set. (Outside the anonymous namespace:
// SubspaceElements::Impl, which has external linkage, holds it.)
struct SubspaceElement {
  const Material<2>* material2 = nullptr;
  const Material<3>* material3 = nullptr;
  LameParameters lame{0.0, 0.0};
  double volume = 0.0;
  int mesh_element = 0;
  Matrix d;  // D_e, Dim^2 x r
};

struct SubspaceElements::Impl {
  int r = 0;
  std::vector<SubspaceElement> elements;
};

namespace {

// Psi(F; 2 lambda, 2 mu) = 2 Psi(F; lambda, mu) at a strained F: what the design's linearity in
// Young's modulus needs.
template <int Dim>
void check_linear_in_modulus(const Material<Dim>& material, const LameParameters& lame) {
  Eigen::Matrix<double, Dim, Dim> F = Eigen::Matrix<double, Dim, Dim>::Identity();
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j) F(i, j) += 0.05 * (i + 1) - 0.03 * (j + 2) * (i == j ? -1.0 : 1.0);
  MaterialEvaluation<Dim> one, two;
  material.evaluate(F, lame, true, false, HessianMode::exact, one);
  material.evaluate(F, LameParameters{2.0 * lame.lambda, 2.0 * lame.mu}, true, false, HessianMode::exact, two);
  const double scale = std::abs(one.energy_density) + one.stress.norm();
  if (!(std::abs(two.energy_density - 2.0 * one.energy_density) + (two.stress - 2.0 * one.stress).norm() <=
        1e-10 * scale))
    throw std::invalid_argument("SubspaceElements: material '" + material.name() +
                                "' is not linear in Young's modulus at fixed Poisson's ratio");
}

template <int Dim>
void gather(const ElasticTerm<Dim>& term, const Vector& p, const Matrix& basis,
            std::vector<SubspaceElement>& out, bool& checked) {
  const int r = static_cast<int>(basis.cols());
  for (int k = 0; k < static_cast<int>(term.elements().size()); ++k) {
    SubspaceElement e;
    if constexpr (Dim == 2)
      e.material2 = &term.material();
    else
      e.material3 = &term.material();
    e.lame = term.element_lame(p, k);
    if (!checked) {
      check_linear_in_modulus<Dim>(term.material(), e.lame);
      checked = true;
    }
    e.volume = term.rest_volume(k);
    e.mesh_element = term.elements()[static_cast<std::size_t>(k)];
    // F_ij = delta_ij + sum_a u_{a,i} dN_a/dX_j: row i + Dim j of D_e.
    e.d = Matrix::Zero(Dim * Dim, r);
    const auto& G = term.shape_gradients(k);
    const auto& vertices = term.element_vertices(k);
    for (int a = 0; a < Dim + 1; ++a)
      for (int i = 0; i < Dim; ++i)
        for (int j = 0; j < Dim; ++j) e.d.row(i + Dim * j) += G(a, j) * basis.row(Dim * vertices[a] + i);
    out.push_back(std::move(e));
  }
}

template <int Dim>
bool add_element(const Material<Dim>& material, const SubspaceElement& e, const Vector& q,
                 double scale, double* energy, Vector* force, Matrix* stiffness) {
  Eigen::Matrix<double, Dim * Dim, 1> f = e.d * q;
  for (int i = 0; i < Dim; ++i) f[i + Dim * i] += 1.0;
  const Eigen::Matrix<double, Dim, Dim> F = Eigen::Map<const Eigen::Matrix<double, Dim, Dim>>(f.data());
  MaterialEvaluation<Dim> m;
  material.evaluate(F, e.lame, force != nullptr, stiffness != nullptr, HessianMode::exact, m);
  if (!std::isfinite(m.energy_density) || (force && !m.stress.allFinite()) ||
      (stiffness && !m.tangent.allFinite()))
    return false;
  const double v = scale * e.volume;
  if (energy) *energy += v * m.energy_density;
  if (force) {
    const Eigen::Map<const Eigen::Matrix<double, Dim * Dim, 1>> stress(m.stress.data());
    force->noalias() += e.d.transpose() * (v * stress);
  }
  if (stiffness) {
    const Matrix td = m.tangent * e.d;
    stiffness->noalias() += v * (e.d.transpose() * td);
  }
  return true;
}

}  // namespace

SubspaceElements::SubspaceElements(const Model& model, const Vector& p, const Matrix& basis,
                                   const std::vector<int>& keep)
    : impl_(std::make_unique<Impl>()) {
  if (basis.rows() != model.num_dofs())
    throw std::invalid_argument("SubspaceElements: the basis has " + std::to_string(basis.rows()) +
                                " rows, the model " + std::to_string(model.num_dofs()) + " DOFs");
  impl_->r = static_cast<int>(basis.cols());
  std::vector<SubspaceElement> all;
  for (const auto& term : model.terms()) {
    bool checked = false;
    if (const auto* t3 = dynamic_cast<const ElasticTerm<3>*>(term.get())) gather<3>(*t3, p, basis, all, checked);
    if (const auto* t2 = dynamic_cast<const ElasticTerm<2>*>(term.get())) gather<2>(*t2, p, basis, all, checked);
  }
  if (all.empty()) throw std::invalid_argument("SubspaceElements: the model has no elastic term");
  if (keep.empty()) {
    impl_->elements = std::move(all);
    return;
  }
  for (int k : keep) {
    if (k < 0 || k >= static_cast<int>(all.size()))
      throw std::invalid_argument("SubspaceElements: element " + std::to_string(k) + " of " +
                                  std::to_string(all.size()));
    impl_->elements.push_back(all[static_cast<std::size_t>(k)]);
  }
}

SubspaceElements::~SubspaceElements() = default;
SubspaceElements::SubspaceElements(SubspaceElements&&) noexcept = default;
SubspaceElements& SubspaceElements::operator=(SubspaceElements&&) noexcept = default;

int SubspaceElements::size() const { return static_cast<int>(impl_->elements.size()); }
int SubspaceElements::reduced_size() const { return impl_->r; }
int SubspaceElements::mesh_element(int k) const {
  return impl_->elements[static_cast<std::size_t>(k)].mesh_element;
}

bool SubspaceElements::add(int k, const Vector& q, double scale, double* energy, Vector* force,
                           Matrix* stiffness) const {
  const SubspaceElement& e = impl_->elements[static_cast<std::size_t>(k)];
  if (e.material3) return add_element<3>(*e.material3, e, q, scale, energy, force, stiffness);
  return add_element<2>(*e.material2, e, q, scale, energy, force, stiffness);
}

}  // namespace tailor
