#include "forward/core/assembler.hpp"

#include <algorithm>
#include <limits>
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
  struct Image {
    int row, col, slot;
    double weight;
  };
  std::vector<Image> images;
  images.reserve(slots.size() / 2 + m);
  for (std::size_t k = 0; k < slots.size(); ++k) {
    const int i = slots[k].row, j = slots[k].col;
    if (i < 0 || j < 0 || i >= model.num_dofs() || j >= model.num_dofs())
      throw std::out_of_range("ReducedAssembler: a Hessian slot lies outside the DOF range");
    for (int s = rb[i]; s < rb[i + 1]; ++s)
      for (int t = rb[j]; t < rb[j + 1]; ++t)
        if (rf[s] <= rf[t]) images.push_back({rf[s], rf[t], static_cast<int>(k), rw[s] * rw[t]});
  }
  if (slots.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::length_error("ReducedAssembler: more Hessian slots than an int can index");
  unit_weights_ = std::all_of(images.begin(), images.end(), [](const Image& im) { return im.weight == 1.0; });

  // 3. The upper-triangular pattern; the diagonal is always present so that a
  //    regularisation shift can be added without changing the pattern.
  Triplets triplets;
  triplets.reserve(images.size() + m);
  for (const auto& im : images) triplets.emplace_back(im.row, im.col, 0.0);
  for (int a = 0; a < m; ++a) triplets.emplace_back(a, a, 0.0);
  pattern_.resize(m, m);
  pattern_.setFromTriplets(triplets.begin(), triplets.end());
  pattern_.makeCompressed();
  pattern_.coeffs().setZero();

  // 4. Group the images by matrix entry (counting sort): entry -> contributing slots.
  const int* outer = pattern_.outerIndexPtr();
  const int* inner = pattern_.innerIndexPtr();
  std::vector<int> entry_of(images.size());
  entry_begin_.assign(pattern_.nonZeros() + 1, 0);
  for (std::size_t t = 0; t < images.size(); ++t) {
    const int* first = inner + outer[images[t].col];
    const int* last = inner + outer[images[t].col + 1];
    entry_of[t] = static_cast<int>(std::lower_bound(first, last, images[t].row) - inner);
    ++entry_begin_[entry_of[t] + 1];
  }
  for (std::size_t e = 0; e + 1 < entry_begin_.size(); ++e) entry_begin_[e + 1] += entry_begin_[e];
  entry_slot_.resize(images.size());
  weight_.assign(unit_weights_ ? 0 : images.size(), 0.0);
  std::vector<std::int64_t> fill(entry_begin_.begin(), entry_begin_.end() - 1);
  for (std::size_t t = 0; t < images.size(); ++t) {
    const auto position = fill[entry_of[t]]++;
    entry_slot_[position] = images[t].slot;
    if (!unit_weights_) weight_[position] = images[t].weight;
  }
}

void ReducedAssembler::evaluate(const Vector& y, const Vector& p, double* energy,
                                Vector* gradient_y, SparseMatrix* hessian_y, HessianMode mode) {
  const Elimination& elim = model_.elimination();
  if (y.size() != elim.num_free())
    throw std::invalid_argument("ReducedAssembler::evaluate: y has the wrong size");
  const Vector x = model_.state(y, p);
  Vector gx;
  if (gradient_y) gx = Vector::Zero(model_.num_dofs());
  if (energy) *energy = 0.0;

  const auto& terms = model_.terms();
  if (hessian_y) {
    cached_.resize(terms.size());
    if (cached_p_.size() != p.size() || !(cached_p_.array() == p.array()).all()) {
      for (CachedHessian& c : cached_) c.valid = false;
      cached_p_ = p;
    }
  }
  for (std::size_t k = 0; k < terms.size(); ++k) {
    EnergyRequest request;
    request.value = energy;
    request.gradient = gradient_y ? &gx : nullptr;
    const bool has_slots = term_slot_begin_[k + 1] > term_slot_begin_[k];
    CachedHessian written;  // what the slots hold after this evaluation, when they are written
    if (hessian_y && has_slots) {
      const CachedHessian& cache = cached_[k];
      written.valid = terms[k]->hessian_is_constant();
      written.revision = written.valid ? terms[k]->hessian_revision() : 0;
      written.mode = mode;
      if (!(written.valid && cache.valid && cache.revision == written.revision && cache.mode == mode)) {
        request.hessian_values = buffer_.data() + term_slot_begin_[k];
        cached_[k].valid = false;  // until the term has written them (it may throw)
      }
    }
    request.hessian_mode = mode;
    if (request.value || request.gradient || request.hessian_values) terms[k]->evaluate(x, p, request);
    if (request.hessian_values) cached_[k] = written;
  }

  if (gradient_y) *gradient_y = elim.reduce(gx);
  if (hessian_y) {
    if (hessian_y->nonZeros() != pattern_.nonZeros() || hessian_y->rows() != pattern_.rows())
      *hessian_y = pattern_;
    double* values = hessian_y->valuePtr();
    const auto num_entries = static_cast<std::ptrdiff_t>(hessian_y->nonZeros());
    const double* slot_values = buffer_.data();
    if (unit_weights_) {
#pragma omp parallel for schedule(static) if (num_entries > 16384)
      for (std::ptrdiff_t e = 0; e < num_entries; ++e) {
        double sum = 0.0;
        for (auto t = entry_begin_[e]; t < entry_begin_[e + 1]; ++t) sum += slot_values[entry_slot_[t]];
        values[e] = sum;
      }
    } else {
#pragma omp parallel for schedule(static) if (num_entries > 16384)
      for (std::ptrdiff_t e = 0; e < num_entries; ++e) {
        double sum = 0.0;
        for (auto t = entry_begin_[e]; t < entry_begin_[e + 1]; ++t) sum += weight_[t] * slot_values[entry_slot_[t]];
        values[e] = sum;
      }
    }
  }
}

LowRankHessian ReducedAssembler::low_rank_hessian(const Vector& y, const Vector& p, HessianMode mode) const {
  LowRankHessian full = model_.low_rank_hessian(model_.state(y, p), p, mode);
  if (!full.empty()) full.factors = Matrix(model_.elimination().basis().transpose() * full.factors);
  return full;
}

}  // namespace tailor
