#include "forward/dynamics/descent_block_jacobi.hpp"

#include "forward/dynamics/descent_tet_kernels.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

namespace tailor {

void BlockJacobiPass::BlockGather::sum(const std::vector<double>& slot_values, double* entries, bool add) const {
  const std::int64_t n = static_cast<std::int64_t>(begin.size()) - 1;
#pragma omp parallel for schedule(static) if (n > 16384)
  for (std::int64_t e = 0; e < n; ++e) {
    double s = add ? entries[e] : 0.0;
    for (std::int64_t t = begin[e]; t < begin[e + 1]; ++t) s += slot_values[static_cast<std::size_t>(slot[t])];
    entries[e] = s;
  }
}

BlockJacobiPass::BlockJacobiPass(const Model& model, int block_size) : model_(model), block_size_(block_size) {
  if (block_size < 1 || block_size > 3)
    throw std::invalid_argument("descent: the preconditioner's block size must be 1, 2 or 3, got " +
                                std::to_string(block_size));
  const Elimination& elim = model.elimination();
  const int n = model.num_dofs();
  if (n % block_size != 0)
    throw std::invalid_argument("descent: " + std::to_string(n) + " DOFs are not blocks of " +
                                std::to_string(block_size));
  if (!elim.is_selection() || model.has_prescribed_parameters())
    throw std::invalid_argument(
        "descent: the model's constraints are not a selection of DOFs (periodicity, handles or prescribed "
        "parameters couple unknowns); the block-Jacobi descent solver needs Dirichlet conditions only: use "
        "Newton");
  // Free index of each DOF, and the blocks: the vertices with at least one free DOF. Each
  // free unknown must move one DOF (two DOFs sharing one would couple two blocks).
  std::vector<int> free_of_dof(static_cast<std::size_t>(n), -1), uses(static_cast<std::size_t>(elim.num_free()), 0);
  for (int i = 0; i < n; ++i)
    for (int t = elim.row_begin()[i]; t < elim.row_begin()[i + 1]; ++t) {
      free_of_dof[i] = elim.row_free()[t];
      if (++uses[static_cast<std::size_t>(free_of_dof[i])] > 1)
        throw std::invalid_argument("descent: free unknown " + std::to_string(free_of_dof[i]) +
                                    " moves several DOFs (periodic or tied constraints); the block-Jacobi "
                                    "descent solver needs Dirichlet conditions only: use Newton");
    }
  const int bs = block_size;
  std::vector<int> block_of_vertex(static_cast<std::size_t>(n / bs), -1);
  for (int v = 0; v < n / bs; ++v) {
    bool any = false;
    for (int k = 0; k < bs; ++k) any = any || free_of_dof[bs * v + k] >= 0;
    if (!any) continue;
    block_of_vertex[v] = num_blocks();
    for (int k = 0; k < bs; ++k) block_free_.push_back(free_of_dof[bs * v + k]);
  }
  // Every term's slots in one buffer, and for each block entry the slots that land in it.
  std::vector<std::pair<std::int64_t, std::int64_t>> constant_pairs, state_pairs;  // (entry, slot)
  std::size_t offset = 0;
  for (const auto& term : model.terms()) {
    HessianPattern pattern;
    term->hessian_pattern(pattern);
    const bool constant = term->hessian_is_constant();
    term_slot_begin_.push_back(offset);
    term_constant_.push_back(constant ? 1 : 0);
    for (std::size_t s = 0; s < pattern.size(); ++s) {
      const auto [row, col] = pattern[s];
      if (row / bs != col / bs || free_of_dof[row] < 0 || free_of_dof[col] < 0) continue;
      const std::int64_t entry =
          static_cast<std::int64_t>(block_of_vertex[row / bs]) * bs * bs + (row % bs) * bs + col % bs;
      (constant ? constant_pairs : state_pairs).emplace_back(entry, static_cast<std::int64_t>(offset + s));
    }
    if (!constant) state_slot_count_ += pattern.size();
    offset += pattern.size();
  }
  term_slot_begin_.push_back(offset);
  slots_.assign(offset, 0.0);
  const std::int64_t entries = static_cast<std::int64_t>(num_blocks()) * bs * bs;
  auto build = [entries](std::vector<std::pair<std::int64_t, std::int64_t>>& pairs, BlockGather& g) {
    std::stable_sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    g.begin.assign(static_cast<std::size_t>(entries) + 1, 0);
    for (const auto& pr : pairs) ++g.begin[static_cast<std::size_t>(pr.first) + 1];
    std::partial_sum(g.begin.begin(), g.begin.end(), g.begin.begin());
    g.slot.resize(pairs.size());
    for (std::size_t t = 0; t < pairs.size(); ++t) g.slot[t] = pairs[t].second;
  };
  build(constant_pairs, constant_gather_);
  build(state_pairs, state_gather_);
  constant_sums_.assign(static_cast<std::size_t>(entries), 0.0);
  block_sums_.assign(static_cast<std::size_t>(entries), 0.0);
}

void BlockJacobiPass::evaluate(const Vector& y, const Vector& p, DescentEvaluation& out, bool with_preconditioner) {
  const Vector x = model_.state(y, p);
  Vector gradient_x = Vector::Zero(x.size());
  double energy = 0.0, magnitude = 0.0;
  bool constant_fresh = constant_valid_ && constant_p_.size() == p.size() && constant_p_ == p;
  std::vector<std::uint64_t> revisions;
  if (with_preconditioner) {
    for (std::size_t t = 0; t < model_.terms().size(); ++t)
      if (term_constant_[t]) revisions.push_back(model_.terms()[t]->hessian_revision());
    constant_fresh = constant_fresh && revisions == constant_revisions_;
  }
  for (std::size_t t = 0; t < model_.terms().size(); ++t) {
    EnergyRequest request;
    request.value = &energy;
    request.gradient = &gradient_x;
    request.hessian_mode = HessianMode::projected;
    const bool has_slots = term_slot_begin_[t + 1] > term_slot_begin_[t];
    if (with_preconditioner && has_slots && !(term_constant_[t] && constant_fresh))
      request.hessian_values = slots_.data() + term_slot_begin_[t];
    const double before = energy;
    model_.terms()[t]->evaluate(x, p, request);
    magnitude += std::abs(energy - before);
  }
  out.energy = energy;
  out.energy_roundoff = 1e3 * std::numeric_limits<double>::epsilon() * magnitude;
  out.gradient = model_.elimination().reduce(gradient_x);
  if (!with_preconditioner) return;
  if (!constant_fresh) {
    constant_gather_.sum(slots_, constant_sums_.data(), false);
    constant_valid_ = true;
    constant_p_ = p;
    constant_revisions_ = std::move(revisions);
  }
  block_sums_ = constant_sums_;
  state_gather_.sum(slots_, block_sums_.data(), true);
  invert_blocks(out.block_inverse);
}

void BlockJacobiPass::invert_blocks(std::vector<double>& inverse) const {
  const int bs = block_size_, bb = bs * bs;
  const int blocks = num_blocks();
  inverse.resize(block_sums_.size());
#pragma omp parallel for schedule(static) if (blocks > 4096)
  for (int b = 0; b < blocks; ++b) {
    double a[9];
    const int* free = block_free_.data() + static_cast<std::ptrdiff_t>(b) * bs;
    for (int i = 0; i < bs; ++i)
      for (int j = 0; j < bs; ++j) {
        const bool used = free[i] >= 0 && free[j] >= 0;
        a[i * bs + j] = used ? block_sums_[static_cast<std::size_t>(b) * bb + i * bs + j] : (i == j ? 1.0 : 0.0);
      }
    // Cholesky, or for a block that is not positive definite (a vertex without mass or
    // stiffness in the projected Hessian) the floored inverse of its absolute diagonal.
    descent_kernels::block_inverse(a, bs, inverse.data() + static_cast<std::ptrdiff_t>(b) * bb);
  }
}

void BlockJacobiPass::apply_inverse(const DescentEvaluation& at, const Vector& gradient, Vector& direction) const {
  const int bs = block_size_, bb = bs * bs;
  const int blocks = num_blocks();
  direction.resize(gradient.size());
#pragma omp parallel for schedule(static) if (blocks > 4096)
  for (int b = 0; b < blocks; ++b) {
    const int* free = block_free_.data() + static_cast<std::ptrdiff_t>(b) * bs;
    const double* inv = at.block_inverse.data() + static_cast<std::ptrdiff_t>(b) * bb;
    for (int i = 0; i < bs; ++i) {
      if (free[i] < 0) continue;
      double s = 0.0;
      for (int j = 0; j < bs; ++j)
        if (free[j] >= 0) s += inv[i * bs + j] * gradient[free[j]];
      direction[free[i]] = s;
    }
  }
}

std::size_t BlockJacobiPass::bytes_per_pass(bool with_preconditioner) const {
  const std::size_t d = sizeof(double);
  const std::size_t n = static_cast<std::size_t>(model_.num_dofs()), m = static_cast<std::size_t>(num_free());
  // x expanded (read y, write x), the full gradient zeroed, scattered into and reduced, the
  // reduced gradient written: about 6 vectors of n or m doubles.
  std::size_t bytes = d * (2 * m + 4 * n);
  if (with_preconditioner) {
    // The state terms' slots written by the element loop, those in diagonal blocks read back by
    // the gather (with their 8-byte indices), the block sums copied, inverted and written.
    bytes += state_slot_count_ * d + state_gather_.slot.size() * (d + sizeof(std::int64_t));
    bytes += block_sums_.size() * 4 * d;
  }
  return bytes;
}

}  // namespace tailor
