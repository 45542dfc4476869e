#pragma once
// Tikhonov: quadratic regularisation of one parameter block towards a prior,
//
//   J(p) = alpha/2 ||W (q - q0)||^2 = alpha/2 sum_i (w_i (q_i - q0_i))^2,
//
// q = p[offset .. offset + size), q0 the prior, W = diag(w) (w = 1 when not given). J does not
// depend on x. Least-squares form: r_i = sqrt(alpha) w_i (q_i - q0_i).
#include "objectives/objective.hpp"

namespace tailor {

class Tikhonov final : public Objective {
 public:
  // Throws std::invalid_argument when offset < 0, size < 1, alpha < 0 or non-finite, or the
  // prior / weights have the wrong size or non-finite entries (weights must also be >= 0).
  Tikhonov(int offset, int size, double alpha, Vector prior, Vector weights = {});

  std::string name() const override { return "tikhonov"; }
  double value(const Vector& x, const Vector& p) const override;
  void add_gradient_x(const Vector& x, const Vector& p, Vector& gx) const override;
  void add_gradient_p(const Vector& x, const Vector& p, Vector& gp) const override;
  bool has_second_derivatives() const override { return true; }
  void add_hessian_times(const Vector& x, const Vector& p, const Vector& dx, const Vector& dp, Vector& out_x,
                         Vector& out_p) const override;

  bool is_least_squares() const override { return true; }
  int num_residuals() const override { return size_; }
  void residuals(const Vector& x, const Vector& p, Vector& r, SparseMatrix* dr_dx, SparseMatrix* dr_dp) const override;

 private:
  void check_parameters(const Vector& p) const;
  int offset_, size_;
  double alpha_;
  Vector prior_, weights_;
};

}  // namespace tailor
