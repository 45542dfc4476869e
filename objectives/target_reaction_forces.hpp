#pragma once
// TargetReactionForces: match the reaction forces of an energy (one term, or the sum of
// several) on a set of DOFs.
//
// The reaction on DOF i is f_i(x, p) = dE/dx_i (x, p): at equilibrium it is the force that
// the supports (Dirichlet DOFs, handles) apply to the body to hold it there, i.e. what a load
// cell at the support reads; the body pushes on the support with -f_i. The measured quantity
// is y = A f, with A either
//   per_dof: y_i = f_{dofs[i]}                             (|dofs| entries), or
//   total:   y_k = sum_{i in dofs, i % dim == k} f_i        (dim entries: the total reaction
//            force over the vertex set, per component; the usual measurement),
// and
//   J(x, p) = 1/2 (y - y*)^T W (y - y*),   W = diag(w), w >= 0 (1 when not given).
// Derivatives, with H = d2E/dx2 (the term's exact Hessian) and M = d2E/dxdp (its mixed block):
//   dJ/dx = H^T A^T W (y - y*),   dJ/dp = M^T A^T W (y - y*),
// evaluated as one Hessian-vector and one mixed-transpose product of the terms (no matrix is
// assembled). Only the elements touching the selected DOFs contribute to f there, so terms
// restricted to those elements give the same J for far less work on large meshes.
// Least-squares form: r = W^{1/2} (A f - y*), dr/dx = W^{1/2} A H, dr/dp = W^{1/2} A M.
//
// Second derivatives are NOT provided (has_second_derivatives() == false): besides the exact
// Gauss-Newton part (A H)^T W (A H) dx + ..., the Hessian of J contains
// sum_i (A^T W (y - y*))_i d3E/dx_i dx dx (and the matching d3E/dx dx dp, d3E/dx dp dp terms),
// third derivatives of the energy that EnergyTerm does not expose. Use the least-squares form
// for Gauss-Newton; add_hessian_times throws.
#include <memory>
#include <vector>

#include "forward/core/energy_term.hpp"
#include "objectives/objective.hpp"

namespace tailor {

class TargetReactionForces final : public Objective {
 public:
  enum class Aggregation { per_dof, total };

  // `term` must outlive this objective (e.g. a term owned by a Model). `num_dofs`: size of the
  // state; `dim`: DOFs per vertex (the component of DOF i is i % dim). `target` has |dofs|
  // (per_dof) or dim (total) entries, `weights` the same number or none. Throws
  // std::invalid_argument on empty / out-of-range / duplicate DOFs, num_dofs not a multiple
  // of dim, wrong sizes, non-finite targets or negative / non-finite weights.
  TargetReactionForces(const EnergyTerm& term, int num_dofs, int dim, std::vector<int> dofs,
                       Aggregation aggregation, Vector target, Vector weights = {});
  // Shares ownership of the term instead.
  TargetReactionForces(std::shared_ptr<const EnergyTerm> term, int num_dofs, int dim, std::vector<int> dofs,
                       Aggregation aggregation, Vector target, Vector weights = {});
  // The reaction of the sum of several terms (e.g. all elastic terms of a model and its
  // external loads); shares their ownership. Throws also when the list is empty or holds null.
  TargetReactionForces(std::vector<std::shared_ptr<const EnergyTerm>> terms, int num_dofs, int dim,
                       std::vector<int> dofs, Aggregation aggregation, Vector target, Vector weights = {});

  std::string name() const override;
  double value(const Vector& x, const Vector& p) const override;
  void add_gradient_x(const Vector& x, const Vector& p, Vector& gx) const override;
  void add_gradient_p(const Vector& x, const Vector& p, Vector& gp) const override;

  bool has_second_derivatives() const override { return false; }
  // Always throws std::logic_error (see above).
  void add_hessian_times(const Vector& x, const Vector& p, const Vector& dx, const Vector& dp, Vector& out_x,
                         Vector& out_p) const override;

  bool is_least_squares() const override { return true; }
  int num_residuals() const override { return static_cast<int>(selection_.rows()); }
  void residuals(const Vector& x, const Vector& p, Vector& r, SparseMatrix* dr_dx,
                 SparseMatrix* dr_dp) const override;

  // y = A f(x, p), the measured reaction.
  Vector reaction(const Vector& x, const Vector& p) const;
  const SparseMatrix& selection() const { return selection_; }  // A
  const Vector& target() const { return target_; }              // y*
  const Vector& weights() const { return weights_; }            // w

 private:
  Vector weighted_misfit(const Vector& x, const Vector& p) const;  // W (A f - y*)
  void check_state(const Vector& x) const;
  void initialize(int dim, const std::vector<int>& dofs, Aggregation aggregation);
  std::vector<std::shared_ptr<const EnergyTerm>> owners_;
  std::vector<const EnergyTerm*> terms_;
  int num_dofs_;
  SparseMatrix selection_;
  Vector target_, weights_;
};

}  // namespace tailor
