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

  // 2. Their images (a, b, w) in y, upper triangle only (a <= b): S^T H S summed entrywise, for
  //    the slots between short rows of S; the others go to the coupled product (see the header).
  struct Image {
    int row, col, slot;
    double weight;
    bool constant;  // of a term whose Hessian is constant (gathered once, see constant_sums_)
  };
  std::vector<char> long_row(static_cast<std::size_t>(model.num_dofs()), 0);
  for (int i = 0; i < model.num_dofs(); ++i) long_row[static_cast<std::size_t>(i)] = rb[i + 1] - rb[i] > kShortRow;
  std::vector<Image> images;
  images.reserve(slots.size() / 2 + m);
  std::vector<char> constant_slot(slots.size(), 0);
  constant_term_.assign(terms_.size(), 0);
  for (std::size_t t = 0; t < terms_.size(); ++t)
    if ((constant_term_[t] = terms_[t]->hessian_is_constant()))
      std::fill(constant_slot.begin() + static_cast<std::ptrdiff_t>(term_slot_begin_[t]),
                constant_slot.begin() + static_cast<std::ptrdiff_t>(term_slot_begin_[t + 1]), 1);
  std::vector<std::size_t> coupled_slots;
  for (std::size_t k = 0; k < slots.size(); ++k) {
    const int i = slots[k].row, j = slots[k].col;
    if (i < 0 || j < 0 || i >= model.num_dofs() || j >= model.num_dofs())
      throw std::out_of_range("ReducedAssembler: a Hessian slot lies outside the DOF range");
    if (long_row[static_cast<std::size_t>(i)] || long_row[static_cast<std::size_t>(j)]) {
      coupled_slots.push_back(k);
      continue;
    }
    for (int s = rb[i]; s < rb[i + 1]; ++s)
      for (int t = rb[j]; t < rb[j + 1]; ++t)
        if (rf[s] <= rf[t])
          images.push_back({rf[s], rf[t], static_cast<int>(k), rw[s] * rw[t], constant_slot[k] != 0});
  }
  if (slots.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::length_error("ReducedAssembler: more Hessian slots than an int can index");
  const std::vector<std::pair<int, int>> coupled_entries = build_coupled_product(slots, coupled_slots);

  // 3. The upper-triangular pattern; the diagonal is always present so that a
  //    regularisation shift can be added without changing the pattern.
  Triplets triplets;
  triplets.reserve(images.size() + m);
  for (const auto& im : images) triplets.emplace_back(im.row, im.col, 0.0);
  for (const auto& [a, b] : coupled_entries) triplets.emplace_back(a, b, 0.0);
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
  for (std::size_t o = 0; o < coupled_entries.size(); ++o) {
    const auto [a, b] = coupled_entries[o];
    coupled_.out_entry[o] = static_cast<int>(std::lower_bound(inner + outer[b], inner + outer[b + 1], a) - inner);
  }
}

std::vector<std::pair<int, int>> ReducedAssembler::build_coupled_product(const HessianPattern& slots,
                                                                       const std::vector<std::size_t>& coupled_slots) {
  CoupledProduct& c = coupled_;
  std::vector<std::pair<int, int>> entries;
  if (coupled_slots.empty()) return entries;
  const Elimination& elim = model_.elimination();
  c.num_free = elim.num_free();
  c.s_begin = elim.row_begin();
  c.s_free = elim.row_free();
  c.s_weight = elim.row_weight();
  const std::vector<int>& rb = c.s_begin;
  const std::vector<int>& rf = c.s_free;
  const std::vector<double>& rw = c.s_weight;

  // H_c: the coupled slots ordered by (row, column), in slot order within an entry.
  std::vector<std::size_t> order(coupled_slots);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t p, std::size_t q) {
    return slots[p].row != slots[q].row ? slots[p].row < slots[q].row : slots[p].col < slots[q].col;
  });
  Gather& g = c.h_gather;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const HessianEntry& e = slots[order[k]];
    const bool new_row = c.h_row.empty() || c.h_row.back() != e.row;
    if (new_row) {
      c.h_row.push_back(e.row);
      c.h_begin.push_back(static_cast<std::int64_t>(c.h_col.size()));
    }
    if (new_row || c.h_col.back() != e.col) {
      c.h_col.push_back(e.col);
      g.begin.push_back(static_cast<std::int64_t>(g.slot.size()));
    }
    g.slot.push_back(static_cast<int>(order[k]));
  }
  g.begin.push_back(static_cast<std::int64_t>(g.slot.size()));
  c.h_begin.push_back(static_cast<std::int64_t>(c.h_col.size()));
  g.unit_weights = true;

  // T = H_c S: row r's columns are the union of S's rows at H_c's columns.
  const int m = c.num_free;
  const auto rows = static_cast<int>(c.h_row.size());
  std::vector<int> mark(static_cast<std::size_t>(m), -1);
  c.t_begin.assign(1, 0);
  for (int r = 0; r < rows; ++r) {
    const auto first = static_cast<std::ptrdiff_t>(c.t_col.size());
    for (auto e = c.h_begin[static_cast<std::size_t>(r)]; e < c.h_begin[static_cast<std::size_t>(r) + 1]; ++e) {
      const int j = c.h_col[static_cast<std::size_t>(e)];
      for (int s = rb[static_cast<std::size_t>(j)]; s < rb[static_cast<std::size_t>(j) + 1]; ++s)
        if (mark[static_cast<std::size_t>(rf[static_cast<std::size_t>(s)])] != r) {
          mark[static_cast<std::size_t>(rf[static_cast<std::size_t>(s)])] = r;
          c.t_col.push_back(rf[static_cast<std::size_t>(s)]);
        }
    }
    std::sort(c.t_col.begin() + first, c.t_col.end());
    c.t_begin.push_back(static_cast<std::int64_t>(c.t_col.size()));
  }

  // S^T over T's rows, grouped by free unknown a (rows in increasing order within a).
  std::vector<std::int64_t> count(static_cast<std::size_t>(m) + 1, 0);
  for (int r = 0; r < rows; ++r) {
    const int i = c.h_row[static_cast<std::size_t>(r)];
    for (int s = rb[static_cast<std::size_t>(i)]; s < rb[static_cast<std::size_t>(i) + 1]; ++s)
      ++count[static_cast<std::size_t>(rf[static_cast<std::size_t>(s)]) + 1];
  }
  std::vector<int> index_of(static_cast<std::size_t>(m), -1);
  c.a_begin.assign(1, 0);
  for (int a = 0; a < m; ++a)
    if (count[static_cast<std::size_t>(a) + 1] > 0) {
      index_of[static_cast<std::size_t>(a)] = static_cast<int>(c.r_free.size());
      c.r_free.push_back(a);
      c.a_begin.push_back(c.a_begin.back() + count[static_cast<std::size_t>(a) + 1]);
    }
  c.a_trow.resize(static_cast<std::size_t>(c.a_begin.back()));
  c.a_tstart.resize(c.a_trow.size());
  c.a_weight.resize(c.a_trow.size());
  std::vector<std::int64_t> fill(c.a_begin.begin(), c.a_begin.end() - 1);
  for (int r = 0; r < rows; ++r) {
    const int i = c.h_row[static_cast<std::size_t>(r)];
    for (int s = rb[static_cast<std::size_t>(i)]; s < rb[static_cast<std::size_t>(i) + 1]; ++s) {
      const int a = rf[static_cast<std::size_t>(s)];
      const auto position = static_cast<std::size_t>(fill[static_cast<std::size_t>(index_of[static_cast<std::size_t>(a)])]++);
      c.a_trow[position] = r;
      c.a_weight[position] = rw[static_cast<std::size_t>(s)];
      const int* row_first = c.t_col.data() + c.t_begin[static_cast<std::size_t>(r)];
      const int* row_last = c.t_col.data() + c.t_begin[static_cast<std::size_t>(r) + 1];
      c.a_tstart[position] = std::lower_bound(row_first, row_last, a) - c.t_col.data();
    }
  }

  // The reduced entries (a, b >= a) that S^T T reaches.
  std::fill(mark.begin(), mark.end(), -1);
  c.out_begin.assign(1, 0);
  for (std::size_t q = 0; q < c.r_free.size(); ++q) {
    const auto first = static_cast<std::ptrdiff_t>(c.out_col.size());
    for (auto position = c.a_begin[q]; position < c.a_begin[q + 1]; ++position) {
      const int r = c.a_trow[static_cast<std::size_t>(position)];
      for (auto t = c.a_tstart[static_cast<std::size_t>(position)]; t < c.t_begin[static_cast<std::size_t>(r) + 1]; ++t) {
        const int b = c.t_col[static_cast<std::size_t>(t)];
        if (mark[static_cast<std::size_t>(b)] != static_cast<int>(q)) {
          mark[static_cast<std::size_t>(b)] = static_cast<int>(q);
          c.out_col.push_back(b);
        }
      }
    }
    std::sort(c.out_col.begin() + first, c.out_col.end());
    c.out_begin.push_back(static_cast<std::int64_t>(c.out_col.size()));
    for (auto o = static_cast<std::size_t>(first); o < c.out_col.size(); ++o) entries.emplace_back(c.r_free[q], c.out_col[o]);
  }
  c.out_entry.assign(c.out_col.size(), -1);
  return entries;
}

void ReducedAssembler::CoupledProduct::add(const double* slot_values, double* values) const {
  std::vector<double> h(h_col.size()), t(t_col.size());
  h_gather.sum(slot_values, h.data(), false);
  const auto rows = static_cast<std::ptrdiff_t>(h_row.size());
  const auto reduced_rows = static_cast<std::ptrdiff_t>(r_free.size());
  const int* rb = s_begin.data();
  const int* rf = s_free.data();
  const double* rw = s_weight.data();
  // Each value is summed in a fixed order whatever the thread count: a row of T over its
  // H_c entries, a reduced entry over its unknown's rows of T.
#pragma omp parallel if (t_col.size() > 16384)
  {
    std::vector<double> acc(static_cast<std::size_t>(num_free), 0.0);
#pragma omp for schedule(static)
    for (std::ptrdiff_t r = 0; r < rows; ++r) {
      for (auto e = h_begin[static_cast<std::size_t>(r)]; e < h_begin[static_cast<std::size_t>(r) + 1]; ++e) {
        const int j = h_col[static_cast<std::size_t>(e)];
        const double v = h[static_cast<std::size_t>(e)];
        for (int s = rb[j]; s < rb[j + 1]; ++s) acc[static_cast<std::size_t>(rf[s])] += v * rw[s];
      }
      for (auto k = t_begin[static_cast<std::size_t>(r)]; k < t_begin[static_cast<std::size_t>(r) + 1]; ++k) {
        double& a = acc[static_cast<std::size_t>(t_col[static_cast<std::size_t>(k)])];
        t[static_cast<std::size_t>(k)] = a;
        a = 0.0;
      }
    }
#pragma omp for schedule(static)
    for (std::ptrdiff_t q = 0; q < reduced_rows; ++q) {
      for (auto position = a_begin[static_cast<std::size_t>(q)]; position < a_begin[static_cast<std::size_t>(q) + 1]; ++position) {
        const double w = a_weight[static_cast<std::size_t>(position)];
        const auto end = t_begin[static_cast<std::size_t>(a_trow[static_cast<std::size_t>(position)]) + 1];
        for (auto k = a_tstart[static_cast<std::size_t>(position)]; k < end; ++k)
          acc[static_cast<std::size_t>(t_col[static_cast<std::size_t>(k)])] += w * t[static_cast<std::size_t>(k)];
      }
      for (auto o = out_begin[static_cast<std::size_t>(q)]; o < out_begin[static_cast<std::size_t>(q) + 1]; ++o) {
        double& a = acc[static_cast<std::size_t>(out_col[static_cast<std::size_t>(o)])];
        values[out_entry[static_cast<std::size_t>(o)]] += a;
        a = 0.0;
      }
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
    if (!coupled_.empty()) coupled_.add(slot_values, values);
  }
}

LowRankHessian ReducedAssembler::low_rank_hessian(const Vector& y, const Vector& p, HessianMode mode) const {
  LowRankHessian full = model_.low_rank_hessian(model_.state(y, p), p, mode);
  if (!full.empty()) full.factors = Matrix(model_.elimination().basis().transpose() * full.factors);
  return full;
}

}  // namespace tailor
