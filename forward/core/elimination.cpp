#include "forward/core/elimination.hpp"

#include <Eigen/SparseQR>
#include <stdexcept>

namespace tailor {

Elimination::Elimination(Vector x0, SparseMatrix basis) : offset_(std::move(x0)), basis_(std::move(basis)) {
  if (basis_.rows() != offset_.size())
    throw std::invalid_argument("Elimination: basis has " + std::to_string(basis_.rows()) +
                                " rows but the offset has " + std::to_string(offset_.size()));
  basis_.makeCompressed();
  build_rows();
}

Elimination Elimination::identity(int num_dofs) {
  SparseMatrix s(num_dofs, num_dofs);
  s.setIdentity();
  return Elimination(Vector::Zero(num_dofs), s);
}

Elimination Elimination::dirichlet(const std::vector<int>& fixed_dofs, const Vector& fixed_values) {
  const int n = static_cast<int>(fixed_values.size());
  std::vector<char> fixed(n, 0);
  for (int d : fixed_dofs) {
    if (d < 0 || d >= n)
      throw std::invalid_argument("Elimination::dirichlet: DOF " + std::to_string(d) +
                                  " out of range [0, " + std::to_string(n) + ")");
    fixed[d] = 1;
  }
  Vector x0 = Vector::Zero(n);
  Triplets triplets;
  int column = 0;
  for (int i = 0; i < n; ++i) {
    if (fixed[i])
      x0[i] = fixed_values[i];
    else
      triplets.emplace_back(i, column++, 1.0);
  }
  SparseMatrix s(n, column);
  s.setFromTriplets(triplets.begin(), triplets.end());
  return Elimination(std::move(x0), std::move(s));
}

void Elimination::build_rows() {
  const int n = num_dofs();
  std::vector<std::vector<std::pair<int, double>>> rows(n);
  for (int c = 0; c < basis_.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(basis_, c); it; ++it)
      if (it.value() != 0.0) rows[it.row()].emplace_back(c, it.value());
  row_begin_.assign(n + 1, 0);
  row_free_.clear();
  row_weight_.clear();
  is_selection_ = true;
  for (int i = 0; i < n; ++i) {
    if (rows[i].size() > 1) is_selection_ = false;
    for (auto [c, w] : rows[i]) {
      if (w != 1.0) is_selection_ = false;
      row_free_.push_back(c);
      row_weight_.push_back(w);
    }
    row_begin_[i + 1] = static_cast<int>(row_free_.size());
  }
}

Vector Elimination::expand(const Vector& y) const { return offset_ + basis_ * y; }
Vector Elimination::expand_direction(const Vector& dy) const { return basis_ * dy; }
Vector Elimination::reduce(const Vector& gx) const { return basis_.transpose() * gx; }

Vector Elimination::restrict_state(const Vector& x) const {
  const Vector r = x - offset_;
  if (is_selection_) {
    Vector y = Vector::Zero(num_free());
    for (int i = 0; i < num_dofs(); ++i)
      if (row_begin_[i + 1] > row_begin_[i]) y[row_free_[row_begin_[i]]] = r[i];
    return y;
  }
  Eigen::SparseQR<SparseMatrix, Eigen::COLAMDOrdering<int>> qr(basis_);
  return qr.solve(r);
}

void Elimination::set_offset(const Vector& x0) {
  if (x0.size() != offset_.size())
    throw std::invalid_argument("Elimination::set_offset: size mismatch");
  offset_ = x0;
}

}  // namespace tailor
