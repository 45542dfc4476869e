#include "forward/solve/hessian_share.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace tailor {

HessianShare::HessianShare(const Model& model, const LinearSolver& solver) {
  const Elimination& elim = model.elimination();
  const auto& rb = elim.row_begin();
  const auto& rf = elim.row_free();
  const int n = elim.num_free();
  // An element belongs to the owner of one of the free unknowns its DOFs map to, chosen by a
  // hash of the smallest (the same choice on every process): an element on the boundary between
  // two processes' rows goes to either with equal odds (the smallest alone would give all of
  // them to the lower rows' owner).
  std::vector<int> free;
  const auto keep = [&](const int* dofs, int count) {
    free.clear();
    for (int k = 0; k < count; ++k)
      for (int s = rb[dofs[k]]; s < rb[dofs[k] + 1]; ++s) free.push_back(rf[s]);
    if (free.empty()) return false;
    std::sort(free.begin(), free.end());
    free.erase(std::unique(free.begin(), free.end()), free.end());
    // splitmix64's finalizer
    std::uint64_t h = static_cast<std::uint64_t>(free.front()) + 0x9e3779b97f4a7c15ULL;
    h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ULL;
    h = (h ^ (h >> 27)) * 0x94d049bb133111ebULL;
    h ^= h >> 31;
    return solver.owns_unknown(free[static_cast<std::size_t>(h % free.size())], n);
  };
  const bool owns_first = n > 0 && solver.owns_unknown(0, n);
  for (const auto& term : model.terms()) {
    std::unique_ptr<EnergyTerm> share;
    if (term->share_by_elements(keep, share)) {
      if (share) {
        terms_.push_back(share.get());
        owned_.push_back(std::move(share));
      }
    } else if (owns_first) {
      terms_.push_back(term.get());
    }
  }
  assembler_ = std::make_unique<ReducedAssembler>(model, terms_, /*hessian=*/true, /*full_diagonal=*/false);
  hessian_ = assembler_->hessian_pattern_matrix();
}

void HessianShare::assemble(const Vector& y, const Vector& p, HessianMode mode) {
  assembler_->evaluate(y, p, nullptr, nullptr, &hessian_, mode);
}

}  // namespace tailor
