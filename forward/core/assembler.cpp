#include "forward/core/assembler.hpp"

#include <algorithm>
#include <stdexcept>

namespace tailor {

ReducedAssembler::ReducedAssembler(const Model& model) : model_(model) {
  const Elimination& elim = model.elimination();
  const auto& rb = elim.row_begin();
  const auto& rf = elim.row_free();
  const auto& rw = elim.row_weight();
  const int m = elim.num_free();

  // 1. All terms' slots, as (row, col) in x.
  HessianPattern slots;
  term_slot_begin_.clear();
  for (const auto& term : model.terms()) {
    term_slot_begin_.push_back(slots.size());
    term->hessian_pattern(slots);
  }
  term_slot_begin_.push_back(slots.size());
  buffer_.assign(slots.size(), 0.0);

  // 2. Their images (a, b, w) in y, upper triangle only (a <= b): S^T H S summed entrywise.
  slot_target_begin_.assign(slots.size() + 1, 0);
  std::vector<std::pair<int, int>> images;
  images.reserve(slots.size());
  weight_.clear();
  for (std::size_t k = 0; k < slots.size(); ++k) {
    const int i = slots[k].row, j = slots[k].col;
    if (i < 0 || j < 0 || i >= model.num_dofs() || j >= model.num_dofs())
      throw std::out_of_range("ReducedAssembler: a Hessian slot lies outside the DOF range");
    for (int s = rb[i]; s < rb[i + 1]; ++s)
      for (int t = rb[j]; t < rb[j + 1]; ++t)
        if (rf[s] <= rf[t]) {
          images.emplace_back(rf[s], rf[t]);
          weight_.push_back(rw[s] * rw[t]);
        }
    slot_target_begin_[k + 1] = static_cast<std::int64_t>(images.size());
  }
  unit_weights_ = std::all_of(weight_.begin(), weight_.end(), [](double w) { return w == 1.0; });

  // 3. The upper-triangular pattern; the diagonal is always present so that a
  //    regularisation shift can be added without changing the pattern.
  Triplets triplets;
  triplets.reserve(images.size() + m);
  for (auto [a, b] : images) triplets.emplace_back(a, b, 0.0);
  for (int a = 0; a < m; ++a) triplets.emplace_back(a, a, 0.0);
  pattern_.resize(m, m);
  pattern_.setFromTriplets(triplets.begin(), triplets.end());
  pattern_.makeCompressed();
  pattern_.coeffs().setZero();

  // 4. Entry index of each image.
  target_.resize(images.size());
  const int* outer = pattern_.outerIndexPtr();
  const int* inner = pattern_.innerIndexPtr();
  for (std::size_t t = 0; t < images.size(); ++t) {
    const auto [a, b] = images[t];
    const int* first = inner + outer[b];
    const int* last = inner + outer[b + 1];
    target_[t] = static_cast<int>(std::lower_bound(first, last, a) - inner);
  }
  if (unit_weights_) weight_.clear();
}

void ReducedAssembler::evaluate(const Vector& y, const Vector& p, double* energy,
                                Vector* gradient_y, SparseMatrix* hessian_y, HessianMode mode) {
  const Elimination& elim = model_.elimination();
  if (y.size() != elim.num_free())
    throw std::invalid_argument("ReducedAssembler::evaluate: y has the wrong size");
  const Vector x = elim.expand(y);
  Vector gx;
  if (gradient_y) gx = Vector::Zero(model_.num_dofs());
  if (energy) *energy = 0.0;

  const auto& terms = model_.terms();
  for (std::size_t k = 0; k < terms.size(); ++k) {
    EnergyRequest request;
    request.value = energy;
    request.gradient = gradient_y ? &gx : nullptr;
    const bool has_slots = term_slot_begin_[k + 1] > term_slot_begin_[k];
    request.hessian_values = (hessian_y && has_slots) ? buffer_.data() + term_slot_begin_[k] : nullptr;
    request.hessian_mode = mode;
    if (request.value || request.gradient || request.hessian_values) terms[k]->evaluate(x, p, request);
  }

  if (gradient_y) *gradient_y = elim.reduce(gx);
  if (hessian_y) {
    if (hessian_y->nonZeros() != pattern_.nonZeros() || hessian_y->rows() != pattern_.rows())
      *hessian_y = pattern_;
    double* values = hessian_y->valuePtr();
    std::fill(values, values + hessian_y->nonZeros(), 0.0);
    const std::size_t num_slots = buffer_.size();
    if (unit_weights_) {
      for (std::size_t s = 0; s < num_slots; ++s)
        for (auto t = slot_target_begin_[s]; t < slot_target_begin_[s + 1]; ++t) values[target_[t]] += buffer_[s];
    } else {
      for (std::size_t s = 0; s < num_slots; ++s)
        for (auto t = slot_target_begin_[s]; t < slot_target_begin_[s + 1]; ++t)
          values[target_[t]] += weight_[t] * buffer_[s];
    }
  }
}

}  // namespace tailor
