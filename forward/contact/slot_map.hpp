#pragma once
// SlotMap: the Hessian slots of a term whose nonzeros move with the state (contact), as a
// fixed list of (row, col) DOF entries chosen before a solve and a lookup from an entry to
// its slot. Entries outside the list are reported, never silently dropped.
#include <cstdint>
#include <unordered_map>

#include "forward/core/types.hpp"

namespace tailor::contact {

class SlotMap {
 public:
  // Both (i, j) and (j, i) are added for i != j; repeated entries keep their first slot.
  void add_block(const std::vector<int>& dofs);
  // The slot of entry (row, col), or -1 when the pattern lacks it.
  int slot(int row, int col) const {
    const auto it = slots_.find(key(row, col));
    return it == slots_.end() ? -1 : it->second;
  }
  const HessianPattern& pattern() const { return pattern_; }
  std::size_t size() const { return pattern_.size(); }
  void clear() {
    slots_.clear();
    pattern_.clear();
  }

 private:
  static std::int64_t key(int row, int col) {
    return (static_cast<std::int64_t>(row) << 32) | static_cast<std::uint32_t>(col);
  }
  std::unordered_map<std::int64_t, int> slots_;
  HessianPattern pattern_;
};

inline void SlotMap::add_block(const std::vector<int>& dofs) {
  for (int r : dofs)
    for (int c : dofs)
      if (slots_.emplace(key(r, c), static_cast<int>(pattern_.size())).second) pattern_.push_back({r, c});
}

}  // namespace tailor::contact
