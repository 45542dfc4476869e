#pragma once
// TargetDofs: match selected entries of the state to target values.
//
//   J(x) = w/2 sum_i (x_{d_i} - t_i)^2,
//
// d_i the selected state entries (DOF indices), t_i their targets, w >= 0 one weight for all.
// For states that are not positions only (a rod's vertex positions followed by its edge twists)
// or targets on some coordinates of a vertex only; TargetPositions is the vertex-wise form for
// states of positions. J does not depend on p. Least-squares form: r_i = sqrt(w) (x_{d_i} - t_i).
#include <vector>

#include "objectives/objective.hpp"

namespace tailor {

class TargetDofs final : public Objective {
 public:
  // Throws std::invalid_argument on sizes that differ, no or negative or repeated DOF indices,
  // non-finite targets, or a negative / non-finite weight.
  TargetDofs(std::vector<int> dofs, Vector targets, double weight = 1.0);

  std::string name() const override { return "target_dofs"; }
  double value(const Vector& x, const Vector& p) const override;
  void add_gradient_x(const Vector& x, const Vector& p, Vector& gx) const override;
  bool has_second_derivatives() const override { return true; }
  void add_hessian_times(const Vector& x, const Vector& p, const Vector& dx, const Vector& dp, Vector& out_x,
                         Vector& out_p) const override;

  bool is_least_squares() const override { return true; }
  int num_residuals() const override { return static_cast<int>(dofs_.size()); }
  void residuals(const Vector& x, const Vector& p, Vector& r, SparseMatrix* dr_dx, SparseMatrix* dr_dp) const override;

  const std::vector<int>& dofs() const { return dofs_; }
  const Vector& targets() const { return targets_; }

 private:
  void check_state(const Vector& x) const;
  std::vector<int> dofs_;
  Vector targets_;
  double weight_;
  int max_dof_ = -1;
};

}  // namespace tailor
