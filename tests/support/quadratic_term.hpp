#pragma once
// Test energies with known derivatives.
#include <cmath>
#include <random>

#include "forward/core/energy_term.hpp"

namespace tailor::testing {

// E(x, p) = 1/2 x^T A x - b^T x + p0 * sum_i x_i^3 / 3 (p may be empty: then cubic off).
class QuadraticTerm final : public EnergyTerm {
 public:
  QuadraticTerm(SparseMatrix A, Vector b) : A_(std::move(A)), b_(std::move(b)) {}
  std::string name() const override { return "quadratic"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& r) const override {
    const double c = p.size() ? p[0] : 0.0;
    if (r.value) *r.value += 0.5 * x.dot(A_ * x) - b_.dot(x) + c * x.array().cube().sum() / 3.0;
    if (r.gradient) *r.gradient += A_ * x - b_ + c * x.array().square().matrix();
    if (r.hessian_values) {
      std::size_t k = 0;
      for (int j = 0; j < A_.outerSize(); ++j)
        for (SparseMatrix::InnerIterator it(A_, j); it; ++it)
          r.hessian_values[k++] = it.value() + (it.row() == it.col() ? 2.0 * c * x[it.row()] : 0.0);
    }
  }
  void hessian_pattern(HessianPattern& pattern) const override {
    for (int j = 0; j < A_.outerSize(); ++j)
      for (SparseMatrix::InnerIterator it(A_, j); it; ++it) pattern.push_back({static_cast<int>(it.row()), j});
  }
  void add_param_gradient(const Vector& x, const Vector& p, Vector& gp) const override {
    if (p.size()) gp[0] += x.array().cube().sum() / 3.0;
  }
  void add_mixed(const Vector& x, const Vector& p, Triplets& m) const override {
    if (p.size())
      for (Eigen::Index i = 0; i < x.size(); ++i) m.emplace_back(static_cast<int>(i), 0, x[i] * x[i]);
  }

 private:
  SparseMatrix A_;
  Vector b_;
};

// A random sparse symmetric positive definite matrix (diagonally dominant), full storage.
inline SparseMatrix random_spd(int n, unsigned seed, double density = 0.3) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Triplets t;
  Vector row_sum = Vector::Zero(n);
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if ((u(rng) + 1.0) / 2.0 < density) {
        const double v = u(rng);
        t.emplace_back(i, j, v);
        t.emplace_back(j, i, v);
        row_sum[i] += std::abs(v);
        row_sum[j] += std::abs(v);
      }
  for (int i = 0; i < n; ++i) t.emplace_back(i, i, row_sum[i] + 1.0 + (u(rng) + 1.0));
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

}  // namespace tailor::testing
