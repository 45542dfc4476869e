#pragma once
// WeightedSum: J(x, p) = sum_k c_k J_k(x, p).
//
// Every derivative is the same weighted sum. Second derivatives are available only when every
// part provides them. The least-squares form exists when every part is least squares and
// every c_k >= 0: the residuals are stacked as r = [sqrt(c_1) r_1; sqrt(c_2) r_2; ...], so
// 1/2 ||r||^2 = sum_k c_k 1/2 ||r_k||^2 = J, with the Jacobians stacked the same way.
#include <vector>

#include "objectives/objective.hpp"

namespace tailor {

class WeightedSum final : public Objective {
 public:
  // Throws std::invalid_argument when there are no parts, a part is null, or the number of
  // coefficients differs from the number of parts, or a coefficient is not finite.
  WeightedSum(std::vector<ObjectivePtr> parts, std::vector<double> coefficients);

  std::string name() const override;
  double value(const Vector& x, const Vector& p) const override;
  void add_gradient_x(const Vector& x, const Vector& p, Vector& gx) const override;
  void add_gradient_p(const Vector& x, const Vector& p, Vector& gp) const override;

  bool has_second_derivatives() const override;
  // Throws std::logic_error when a part has no second derivatives.
  void add_hessian_times(const Vector& x, const Vector& p, const Vector& dx, const Vector& dp, Vector& out_x,
                         Vector& out_p) const override;

  bool is_least_squares() const override;
  int num_residuals() const override;
  // Throws std::logic_error when !is_least_squares().
  void residuals(const Vector& x, const Vector& p, Vector& r, SparseMatrix* dr_dx, SparseMatrix* dr_dp) const override;

  const std::vector<ObjectivePtr>& parts() const { return parts_; }
  const std::vector<double>& coefficients() const { return coefficients_; }

 private:
  std::vector<ObjectivePtr> parts_;
  std::vector<double> coefficients_;
};

}  // namespace tailor
