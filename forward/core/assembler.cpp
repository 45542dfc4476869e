#include "forward/core/assembler.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace tailor {

namespace {

std::vector<const EnergyTerm*> all_terms(const Model& model) {
  std::vector<const EnergyTerm*> terms;
  for (const auto& term : model.terms()) terms.push_back(term.get());
  return terms;
}

}  // namespace

ReducedAssembler::ReducedAssembler(const Model& model) : ReducedAssembler(model, all_terms(model)) {}

ReducedAssembler::ReducedAssembler(const Model& model, std::vector<const EnergyTerm*> terms, bool hessian,
                                   bool full_diagonal)
    : model_(model), terms_(std::move(terms)), hessian_(hessian) {
  term_slot_begin_.assign(terms_.size() + 1, 0);
  if (!hessian_) return;
  const Elimination& elim = model.elimination();
  const auto& rb = elim.row_begin();
  const auto& rf = elim.row_free();
  const auto& rw = elim.row_weight();
  const int m = elim.num_free();

  // 1. All terms' slots, as (row, col) in x.
  HessianPattern slots;
  term_slot_begin_.clear();
  for (const EnergyTerm* term : terms_) {
    term_slot_begin_.push_back(slots.size());
    term->hessian_pattern(slots);
  }
  term_slot_begin_.push_back(slots.size());
  buffer_.assign(slots.size(), 0.0);

  // 2. Their images (a, b, w) in y, upper triangle only (a <= b): S^T H S summed entrywise.
  struct Image {
    int row, col, slot;
    double weight;
    bool constant;  // of a term whose Hessian is constant (gathered once, see constant_sums_)
  };
  std::vector<Image> images;
  images.reserve(slots.size() / 2 + m);
  std::vector<char> constant_slot(slots.size(), 0);
  constant_term_.assign(terms_.size(), 0);
  for (std::size_t t = 0; t < terms_.size(); ++t)
    if ((constant_term_[t] = terms_[t]->hessian_is_constant()))
      std::fill(constant_slot.begin() + static_cast<std::ptrdiff_t>(term_slot_begin_[t]),
                constant_slot.begin() + static_cast<std::ptrdiff_t>(term_slot_begin_[t + 1]), 1);
  for (std::size_t k = 0; k < slots.size(); ++k) {
    const int i = slots[k].row, j = slots[k].col;
    if (i < 0 || j < 0 || i >= model.num_dofs() || j >= model.num_dofs())
      throw std::out_of_range("ReducedAssembler: a Hessian slot lies outside the DOF range");
    for (int s = rb[i]; s < rb[i + 1]; ++s)
      for (int t = rb[j]; t < rb[j + 1]; ++t)
        if (rf[s] <= rf[t])
          images.push_back({rf[s], rf[t], static_cast<int>(k), rw[s] * rw[t], constant_slot[k] != 0});
  }
  if (slots.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::length_error("ReducedAssembler: more Hessian slots than an int can index");

  // 3. The upper-triangular pattern; the diagonal is always present so that a
  //    regularisation shift can be added without changing the pattern.
  Triplets triplets;
  triplets.reserve(images.size() + m);
  for (const auto& im : images) triplets.emplace_back(im.row, im.col, 0.0);
  if (full_diagonal)
    for (int a = 0; a < m; ++a) triplets.emplace_back(a, a, 0.0);
  pattern_.resize(m, m);
  pattern_.setFromTriplets(triplets.begin(), triplets.end());
  pattern_.makeCompressed();
  pattern_.coeffs().setZero();

  // 4. Group the images by matrix entry (counting sort), separately for the constant terms'
  //    slots and the others: entry -> contributing slots, in slot order within an entry.
  const int* outer = pattern_.outerIndexPtr();
  const int* inner = pattern_.innerIndexPtr();
  std::vector<int> entry_of(images.size());
  for (std::size_t t = 0; t < images.size(); ++t) {
    const int* first = inner + outer[images[t].col];
    const int* last = inner + outer[images[t].col + 1];
    entry_of[t] = static_cast<int>(std::lower_bound(first, last, images[t].row) - inner);
  }
  for (const bool constant : {true, false}) {
    Gather& gather = constant ? constant_gather_ : state_gather_;
    gather.begin.assign(pattern_.nonZeros() + 1, 0);
    std::size_t count = 0;
    gather.unit_weights = true;
    for (std::size_t t = 0; t < images.size(); ++t)
      if (images[t].constant == constant) {
        ++gather.begin[entry_of[t] + 1];
        ++count;
        gather.unit_weights = gather.unit_weights && images[t].weight == 1.0;
      }
    for (std::size_t e = 0; e + 1 < gather.begin.size(); ++e) gather.begin[e + 1] += gather.begin[e];
    gather.slot.resize(count);
    gather.weight.assign(gather.unit_weights ? 0 : count, 0.0);
    std::vector<std::int64_t> fill(gather.begin.begin(), gather.begin.end() - 1);
    for (std::size_t t = 0; t < images.size(); ++t)
      if (images[t].constant == constant) {
        const auto position = fill[entry_of[t]]++;
        gather.slot[position] = images[t].slot;
        if (!gather.unit_weights) gather.weight[position] = images[t].weight;
      }
  }
}

void ReducedAssembler::Gather::sum(const double* slot_values, double* out, bool add) const {
  const auto num_entries = static_cast<std::ptrdiff_t>(begin.size()) - 1;
  const std::int64_t* b = begin.data();
  const int* s = slot.data();
  if (unit_weights) {
#pragma omp parallel for schedule(static) if (num_entries > 16384)
    for (std::ptrdiff_t e = 0; e < num_entries; ++e) {
      double sum = add ? out[e] : 0.0;
      for (auto t = b[e]; t < b[e + 1]; ++t) sum += slot_values[s[t]];
      out[e] = sum;
    }
  } else {
    const double* w = weight.data();
#pragma omp parallel for schedule(static) if (num_entries > 16384)
    for (std::ptrdiff_t e = 0; e < num_entries; ++e) {
      double sum = add ? out[e] : 0.0;
      for (auto t = b[e]; t < b[e + 1]; ++t) sum += w[t] * slot_values[s[t]];
      out[e] = sum;
    }
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

  const auto& terms = terms_;
  if (hessian_y && !hessian_)
    throw std::logic_error("ReducedAssembler::evaluate: a Hessian from an assembler built without one");
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
        if (constant_term_[k]) constant_sums_valid_ = false;
      }
    }
    request.hessian_mode = mode;
    if (request.value || request.gradient || request.hessian_values) terms[k]->evaluate(x, p, request);
    if (request.hessian_values) {
      cached_[k] = written;
      if (constant_term_[k]) constant_sums_valid_ = false;
    }
  }

  if (gradient_y) *gradient_y = elim.reduce(gx);
  if (hessian_y) {
    if (hessian_y->nonZeros() != pattern_.nonZeros() || hessian_y->rows() != pattern_.rows())
      *hessian_y = pattern_;
    double* values = hessian_y->valuePtr();
    const double* slot_values = buffer_.data();
    if (constant_gather_.empty()) {
      state_gather_.sum(slot_values, values, false);
    } else {
      if (!constant_sums_valid_) {
        constant_sums_.resize(static_cast<std::size_t>(pattern_.nonZeros()));
        constant_gather_.sum(slot_values, constant_sums_.data(), false);
        constant_sums_valid_ = true;
      }
      std::copy(constant_sums_.begin(), constant_sums_.end(), values);
      if (!state_gather_.empty()) state_gather_.sum(slot_values, values, true);
    }
  }
}

LowRankHessian ReducedAssembler::low_rank_hessian(const Vector& y, const Vector& p, HessianMode mode) const {
  LowRankHessian full = model_.low_rank_hessian(model_.state(y, p), p, mode);
  if (!full.empty()) full.factors = Matrix(model_.elimination().basis().transpose() * full.factors);
  return full;
}

}  // namespace tailor
