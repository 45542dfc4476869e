#pragma once
// LinearObservations: weighted misfit of linear functionals of the state.
//
//   J(x) = 1/2 sum_i c_i ((B x)_i - t_i)^2,
//
// B a sparse k x n matrix (row i: the coefficients of observation i over the state's entries),
// t the k targets, c >= 0 the k weights. For observations that are combinations of entries,
// such as the mean position of a handle's vertices (TargetDofs is the special case of single
// entries). J does not depend on p. Least-squares form: r_i = sqrt(c_i) ((B x)_i - t_i).
#include "objectives/objective.hpp"

namespace tailor {

class LinearObservations final : public Objective {
 public:
  // Throws std::invalid_argument on sizes that differ, no observations, non-finite entries or a
  // negative weight.
  LinearObservations(SparseMatrix observations, Vector targets, Vector weights);

  std::string name() const override { return "linear_observations"; }
  double value(const Vector& x, const Vector& p) const override;
  void add_gradient_x(const Vector& x, const Vector& p, Vector& gx) const override;
  bool has_second_derivatives() const override { return true; }
  void add_hessian_times(const Vector& x, const Vector& p, const Vector& dx, const Vector& dp, Vector& out_x,
                         Vector& out_p) const override;

  bool is_least_squares() const override { return true; }
  int num_residuals() const override { return static_cast<int>(targets_.size()); }
  void residuals(const Vector& x, const Vector& p, Vector& r, SparseMatrix* dr_dx, SparseMatrix* dr_dp) const override;

  // B x - t.
  Vector misfit(const Vector& x) const;

 private:
  void check_state(const Vector& x) const;
  SparseMatrix observations_;
  Vector targets_, weights_;
};

}  // namespace tailor
