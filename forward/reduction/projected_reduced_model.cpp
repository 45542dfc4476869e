#include "forward/reduction/projected_reduced_model.hpp"

#include <stdexcept>

namespace tailor {

ProjectedReducedModel::ProjectedReducedModel(const Model& model, Vector p, Vector x0, Matrix basis)
    : model_(model), p_(std::move(p)), x0_(std::move(x0)), basis_(std::move(basis)) {
  if (x0_.size() != model.num_dofs() || basis_.rows() != model.num_dofs())
    throw std::invalid_argument("ProjectedReducedModel: the state and the basis need " +
                                std::to_string(model.num_dofs()) + " rows");
}

void ProjectedReducedModel::evaluate(const Vector& q, double* energy, Vector* force,
                                     Matrix* stiffness) const {
  if (q.size() != basis_.cols()) throw std::invalid_argument("ProjectedReducedModel: q has the wrong size");
  const Vector x = x0_ + basis_ * q;
  if (energy) *energy = model_.energy(x, p_);
  if (force) *force = basis_.transpose() * model_.gradient(x, p_);
  if (stiffness) {
    // One assembly of each term's exact Hessian, then a sparse-dense product with the basis.
    Matrix k_phi = Matrix::Zero(basis_.rows(), basis_.cols());
    for (const auto& term : model_.terms()) k_phi += term->hessian(x, p_, HessianMode::exact) * basis_;
    *stiffness = basis_.transpose() * k_phi;
    *stiffness = 0.5 * (*stiffness + stiffness->transpose()).eval();
  }
}

}  // namespace tailor
