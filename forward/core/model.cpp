#include "forward/core/model.hpp"

#include <algorithm>
#include <stdexcept>

namespace tailor {

int ParameterLayout::add(const std::string& name, int size) {
  if (contains(name)) throw std::invalid_argument("ParameterLayout: block '" + name + "' exists already");
  if (size < 0) throw std::invalid_argument("ParameterLayout: negative size for '" + name + "'");
  blocks_.push_back({name, size_, size});
  size_ += size;
  return blocks_.back().offset;
}

const ParameterLayout::Block& ParameterLayout::at(const std::string& name) const {
  for (const auto& b : blocks_)
    if (b.name == name) return b;
  throw std::out_of_range("ParameterLayout: no parameter block named '" + name + "'");
}

bool ParameterLayout::contains(const std::string& name) const {
  return std::any_of(blocks_.begin(), blocks_.end(), [&](const Block& b) { return b.name == name; });
}

Model::Model(int num_dofs) : num_dofs_(num_dofs), elimination_(Elimination::identity(num_dofs)) {}

void Model::set_elimination(Elimination elimination) {
  if (elimination.num_dofs() != num_dofs_)
    throw std::invalid_argument("Model::set_elimination: constraint has " +
                                std::to_string(elimination.num_dofs()) + " DOFs, model has " +
                                std::to_string(num_dofs_));
  elimination_ = std::move(elimination);
}

void Model::set_prescribed_parameters(SparseMatrix prescribed) {
  if (prescribed.rows() != num_dofs_ || prescribed.cols() != parameters_.size())
    throw std::invalid_argument("Model::set_prescribed_parameters: expected a " + std::to_string(num_dofs_) + " x " +
                                std::to_string(parameters_.size()) + " matrix");
  const auto& rb = elimination_.row_begin();
  for (int c = 0; c < prescribed.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(prescribed, c); it; ++it)
      if (rb[it.row() + 1] > rb[it.row()])
        throw std::invalid_argument("Model::set_prescribed_parameters: DOF " + std::to_string(it.row()) +
                                    " is free; only constrained DOFs can be prescribed by parameters");
  prescribed.makeCompressed();
  prescribed_ = std::move(prescribed);
}

int Model::add_prescribed_displacements(const std::string& name, const std::vector<int>& dofs) {
  // Validate before touching the layout, so a rejected call leaves the model unchanged.
  const auto& rb = elimination_.row_begin();
  for (int d : dofs) {
    if (d < 0 || d >= num_dofs_)
      throw std::invalid_argument("Model::add_prescribed_displacements: DOF " + std::to_string(d) + " out of range");
    if (rb[d + 1] > rb[d])
      throw std::invalid_argument("Model::add_prescribed_displacements: DOF " + std::to_string(d) +
                                  " is free; only constrained DOFs can be prescribed by parameters");
  }
  const int offset = parameters_.add(name, static_cast<int>(dofs.size()));
  for (std::size_t k = 0; k < dofs.size(); ++k) prescribed_triplets_.emplace_back(dofs[k], offset + static_cast<int>(k), 1.0);
  SparseMatrix d(num_dofs_, parameters_.size());
  d.setFromTriplets(prescribed_triplets_.begin(), prescribed_triplets_.end());
  set_prescribed_parameters(std::move(d));
  return offset;
}

Vector Model::state(const Vector& y, const Vector& p) const {
  Vector x = elimination_.expand(y);
  if (has_prescribed_parameters()) {
    if (p.size() != prescribed_.cols())
      throw std::invalid_argument("Model::state: the parameter vector has " + std::to_string(p.size()) +
                                  " entries, the prescribed map expects " + std::to_string(prescribed_.cols()));
    x += prescribed_ * p;
  }
  return x;
}

double Model::energy(const Vector& x, const Vector& p) const {
  double e = 0.0;
  for (const auto& t : terms_) e += t->value(x, p);
  return e;
}

Vector Model::gradient(const Vector& x, const Vector& p) const {
  Vector g = Vector::Zero(num_dofs_);
  for (const auto& t : terms_) t->add_gradient(x, p, g);
  return g;
}

Vector Model::param_gradient(const Vector& x, const Vector& p) const {
  Vector gp = Vector::Zero(p.size());
  for (const auto& t : terms_) t->add_param_gradient(x, p, gp);
  return gp;
}

SparseMatrix Model::mixed(const Vector& x, const Vector& p) const {
  Triplets triplets;
  for (const auto& t : terms_) t->add_mixed(x, p, triplets);
  SparseMatrix m(num_dofs_, p.size());
  m.setFromTriplets(triplets.begin(), triplets.end());
  return m;
}

Vector Model::hessian_times(const Vector& x, const Vector& p, const Vector& w) const {
  Vector out = Vector::Zero(num_dofs_);
  for (const auto& t : terms_) t->add_hessian_times(x, p, w, out);
  return out;
}

LowRankHessian Model::low_rank_hessian(const Vector& x, const Vector& p, HessianMode mode) const {
  LowRankHessian update;
  for (const auto& t : terms_) t->add_low_rank_hessian(x, p, update, mode);
  return update;
}

Vector Model::mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w) const {
  Vector out = Vector::Zero(p.size());
  for (const auto& t : terms_) t->add_mixed_transpose_times(x, p, w, out);
  return out;
}

double Model::max_step(const Vector& x, const Vector& dx) const {
  double alpha = 1.0;
  for (const auto& t : terms_) alpha = std::min(alpha, t->max_step(x, dx));
  return alpha;
}

bool Model::hessian_is_constant() const {
  for (const auto& term : terms_)
    if (!term->hessian_is_constant()) return false;
  return true;
}

std::vector<std::uint64_t> Model::hessian_revisions() const {
  std::vector<std::uint64_t> revisions;
  revisions.reserve(terms_.size());
  for (const auto& term : terms_) revisions.push_back(term->hessian_revision());
  return revisions;
}

}  // namespace tailor
