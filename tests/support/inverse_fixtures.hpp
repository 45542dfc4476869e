#pragma once
// Test-local inverse-problem pieces that do not depend on the objectives/ and parameterization
// libraries (so the adjoint tests check the adjoint alone).
#include <cmath>
#include <vector>

#include "adjoint/parameterization.hpp"
#include "objectives/objective.hpp"

namespace tailor::testing {

// p = [exp(z) scattered into the first `n` entries, base for the rest]: per-element log-moduli.
class LogModuliMap final : public Parameterization {
 public:
  LogModuliMap(Vector base, int n) : base_(std::move(base)), n_(n) {}
  std::string name() const override { return "log_moduli"; }
  int num_design() const override { return n_; }
  int num_params() const override { return static_cast<int>(base_.size()); }
  Vector apply(const Vector& z) const override {
    Vector p = base_;
    p.head(n_) = z.array().exp().matrix();
    return p;
  }
  Vector jacobian_times(const Vector& z, const Vector& dz) const override {
    Vector dp = Vector::Zero(base_.size());
    dp.head(n_) = (z.array().exp() * dz.array()).matrix();
    return dp;
  }
  Vector jacobian_transpose_times(const Vector& z, const Vector& w) const override {
    return (z.array().exp() * w.head(n_).array()).matrix();
  }
  Vector second_derivative_times(const Vector& z, const Vector& w, const Vector& dz) const override {
    return (z.array().exp() * w.head(n_).array() * dz.array()).matrix();
  }

 private:
  Vector base_;
  int n_;
};

// J = 1/2 sum over the listed DOFs of (x_i - target_i)^2 + c/2 |p_head|^2 (the last part
// exercises dJ/dp); least-squares form r = [x_S - target; sqrt(c) p_head].
class DofTargetObjective final : public Objective {
 public:
  DofTargetObjective(std::vector<int> dofs, Vector target, double c = 0.0, int head = 0)
      : dofs_(std::move(dofs)), target_(std::move(target)), c_(c), head_(head) {}
  std::string name() const override { return "dof_target"; }
  double value(const Vector& x, const Vector& p) const override {
    double j = 0.0;
    for (std::size_t k = 0; k < dofs_.size(); ++k) j += 0.5 * std::pow(x[dofs_[k]] - target_[k], 2);
    return j + 0.5 * c_ * p.head(head_).squaredNorm();
  }
  void add_gradient_x(const Vector& x, const Vector&, Vector& gx) const override {
    for (std::size_t k = 0; k < dofs_.size(); ++k) gx[dofs_[k]] += x[dofs_[k]] - target_[k];
  }
  void add_gradient_p(const Vector&, const Vector& p, Vector& gp) const override { gp.head(head_) += c_ * p.head(head_); }
  bool has_second_derivatives() const override { return true; }
  void add_hessian_times(const Vector&, const Vector&, const Vector& dx, const Vector& dp, Vector& out_x,
                         Vector& out_p) const override {
    for (int d : dofs_) out_x[d] += dx[d];
    out_p.head(head_) += c_ * dp.head(head_);
  }
  bool is_least_squares() const override { return true; }
  int num_residuals() const override { return static_cast<int>(dofs_.size()) + head_; }
  void residuals(const Vector& x, const Vector& p, Vector& r, SparseMatrix* dr_dx, SparseMatrix* dr_dp) const override {
    const int m = static_cast<int>(dofs_.size());
    r.resize(m + head_);
    for (int k = 0; k < m; ++k) r[k] = x[dofs_[k]] - target_[k];
    r.tail(head_) = std::sqrt(c_) * p.head(head_);
    if (dr_dx) {
      Triplets t;
      for (int k = 0; k < m; ++k) t.emplace_back(k, dofs_[k], 1.0);
      dr_dx->resize(m + head_, x.size());
      dr_dx->setFromTriplets(t.begin(), t.end());
    }
    if (dr_dp) {
      Triplets t;
      for (int k = 0; k < head_; ++k) t.emplace_back(m + k, k, std::sqrt(c_));
      dr_dp->resize(m + head_, p.size());
      dr_dp->setFromTriplets(t.begin(), t.end());
    }
  }

 private:
  std::vector<int> dofs_;
  Vector target_;
  double c_;
  int head_;
};

}  // namespace tailor::testing
