#include "forward/core/energy_term.hpp"

namespace tailor {

double EnergyTerm::value(const Vector& x, const Vector& p) const {
  double e = 0.0;
  EnergyRequest request;
  request.value = &e;
  evaluate(x, p, request);
  return e;
}

void EnergyTerm::add_gradient(const Vector& x, const Vector& p, Vector& gradient) const {
  EnergyRequest request;
  request.gradient = &gradient;
  evaluate(x, p, request);
}

void LowRankHessian::append(const Matrix& F, const Matrix& G, double scale) {
  if (F.cols() == 0) return;
  const Eigen::Index k = factors.cols(), a = F.cols();
  Matrix f(F.rows(), k + a), g = Matrix::Zero(k + a, k + a);
  if (k > 0) {
    f.leftCols(k) = factors;
    g.topLeftCorner(k, k) = core;
  }
  f.rightCols(a) = F;
  g.bottomRightCorner(a, a) = scale * G;
  factors = std::move(f);
  core = std::move(g);
}

void LowRankHessian::add_times(const Vector& w, Vector& out) const {
  if (empty()) return;
  out += factors * (core * (factors.transpose() * w));
}

void EnergyTerm::add_hessian_times(const Vector& x, const Vector& p, const Vector& w, Vector& out,
                                   HessianMode mode) const {
  LowRankHessian low_rank;
  add_low_rank_hessian(x, p, low_rank, mode);
  low_rank.add_times(w, out);
  HessianPattern pattern;
  hessian_pattern(pattern);
  if (pattern.empty()) return;
  std::vector<double> values(pattern.size(), 0.0);
  EnergyRequest request;
  request.hessian_values = values.data();
  request.hessian_mode = mode;
  evaluate(x, p, request);
  for (std::size_t k = 0; k < pattern.size(); ++k) out[pattern[k].row] += values[k] * w[pattern[k].col];
}

void EnergyTerm::add_mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w,
                                           Vector& gradient_p) const {
  Triplets mixed;
  add_mixed(x, p, mixed);
  for (const auto& t : mixed) gradient_p[t.col()] += t.value() * w[t.row()];
}

SparseMatrix EnergyTerm::hessian(const Vector& x, const Vector& p, HessianMode mode) const {
  HessianPattern pattern;
  hessian_pattern(pattern);
  std::vector<double> values(pattern.size(), 0.0);
  EnergyRequest request;
  request.hessian_values = values.data();
  request.hessian_mode = mode;
  if (!values.empty()) evaluate(x, p, request);
  Triplets triplets;
  triplets.reserve(pattern.size());
  for (std::size_t k = 0; k < pattern.size(); ++k)
    triplets.emplace_back(pattern[k].row, pattern[k].col, values[k]);
  const auto n = static_cast<int>(x.size());
  SparseMatrix h(n, n);
  h.setFromTriplets(triplets.begin(), triplets.end());
  return h;
}

}  // namespace tailor
