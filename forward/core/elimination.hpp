#pragma once
// Constraints by elimination: x = x0 + S y, with y the free unknowns. Dirichlet conditions
// select DOFs out of y; handles and periodicity plug into the same form (rows of S with one
// or several entries).
#include <string>

#include "forward/core/types.hpp"

namespace tailor {

class Elimination {
 public:
  // No constraint: S = I, x0 = 0.
  static Elimination identity(int num_dofs);
  // Fix the listed DOFs at the values they have in `fixed_values` (size num_dofs); the
  // remaining DOFs are free, in increasing order. Throws std::invalid_argument on an index
  // out of range.
  static Elimination dirichlet(const std::vector<int>& fixed_dofs, const Vector& fixed_values);
  // General form. S must have as many rows as x0.
  Elimination(Vector x0, SparseMatrix basis);

  int num_dofs() const { return static_cast<int>(offset_.size()); }
  int num_free() const { return static_cast<int>(basis_.cols()); }
  const Vector& offset() const { return offset_; }      // x0
  const SparseMatrix& basis() const { return basis_; }  // S (n x m)
  // Row-wise view of S: for DOF i, the free indices and weights it depends on.
  const std::vector<int>& row_begin() const { return row_begin_; }
  const std::vector<int>& row_free() const { return row_free_; }
  const std::vector<double>& row_weight() const { return row_weight_; }

  Vector expand(const Vector& y) const;            // x0 + S y
  Vector expand_direction(const Vector& dy) const; // S dy
  Vector reduce(const Vector& gx) const;           // S^T gx
  // A y with expand(y) == x when x is attainable (exact for selection-type S, least
  // squares otherwise).
  Vector restrict_state(const Vector& x) const;
  // Prescribed DOF values may change (e.g. a load step moves a handle); S stays.
  void set_offset(const Vector& x0);
  // True when every DOF is either fixed or equal to exactly one free unknown with weight 1.
  bool is_selection() const { return is_selection_; }

 private:
  void build_rows();
  Vector offset_;
  SparseMatrix basis_;
  std::vector<int> row_begin_, row_free_;
  std::vector<double> row_weight_;
  bool is_selection_ = false;
};

}  // namespace tailor
