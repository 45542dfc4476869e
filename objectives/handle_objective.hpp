#pragma once
// HandleObjective: the handle term of heterogeneous material design (Xu, Li, Chen, Barbic,
// TOG 2015; docs/methods.md section 5). Handles are vertex sets whose displacements u~ are design
// parameters (prescribed DOFs, x = x0 + D p + S y, see Model::add_prescribed_displacements);
// each handle asks for a force fbar (what it applies to the body) and a displacement ubar:
//
//   J(x, p) = alpha/2 sum_h W_h |f_h(x, p) - fbar_h|^2 + alpha beta/2 sum_h |u~_h - ubar_h|^2,
//
// f_h = A_h dE/dx the reaction of the energy E on handle h's DOFs (the force the handle applies
// to the body; A_h sums per component over the handle, or keeps every vertex, see Handle). At
// the equilibrium of the free DOFs under the external loads fhat, with the handles held at u~,
// f = K~ u~ + K21 K11^-1 fhat for a linear material, K~ = K22 - K21 K11^-1 K12 (block 2: the
// handle DOFs), which is the paper's objective; for nonlinear materials f is the nonlinear
// reaction. Handles without fbar have no force term, handles without ubar no displacement term.
//
// Built from existing objectives: one TargetReactionForces per handle with a force target
// (coefficient alpha, weights W_h) and one Tikhonov on the u~ block (coefficient alpha beta,
// weight 0 on handles without ubar), summed by a WeightedSum. Least squares; no second
// derivatives (see TargetReactionForces).
#include <memory>
#include <vector>

#include "objectives/objective.hpp"
#include "objectives/target_reaction_forces.hpp"
#include "objectives/weighted_sum.hpp"

namespace tailor {

struct Handle {
  std::vector<int> vertices;  // distinct; the handle's DOFs are dim * v + k, vertex by vertex
  // ubar: empty (no displacement target), 1 x dim (the same for every vertex) or
  // |vertices| x dim. Length units of the mesh.
  Matrix target_displacement;
  // fbar: empty (no force target), dim entries (the total force the handle applies to the body,
  // summed over its vertices) or dim * |vertices| entries (per vertex, interleaved).
  Vector target_force;
  double weight = 1.0;  // W_h >= 0, on the squared force misfit
};

struct HandleObjectiveOptions {
  double alpha = 1.0;  // >= 0: scales both handle terms
  double beta = 1.0;   // >= 0: displacement vs force, units (force / length)^2
};

class HandleObjective final : public Objective {
 public:
  // `reaction_terms`: terms whose summed gradient at the handle DOFs is the model's (the
  // model's terms, or copies restricted to the elements touching the handles: same values, less
  // work). `displacement_offset`: offset in p of the u~ block, |u~| = dim * sum_h |vertices_h|,
  // handle by handle, vertex by vertex, component by component (the order of dofs()).
  // Throws std::invalid_argument on no handles, empty / out-of-range / repeated vertices, wrong
  // target sizes, non-finite targets, a handle without any target, negative weights, alpha or
  // beta.
  HandleObjective(std::vector<std::shared_ptr<const EnergyTerm>> reaction_terms, int num_dofs, int dim,
                  std::vector<Handle> handles, int displacement_offset, HandleObjectiveOptions options = {});

  std::string name() const override { return "handles"; }
  double value(const Vector& x, const Vector& p) const override { return sum_->value(x, p); }
  void add_gradient_x(const Vector& x, const Vector& p, Vector& gx) const override {
    sum_->add_gradient_x(x, p, gx);
  }
  void add_gradient_p(const Vector& x, const Vector& p, Vector& gp) const override {
    sum_->add_gradient_p(x, p, gp);
  }
  bool has_second_derivatives() const override { return sum_->has_second_derivatives(); }
  void add_hessian_times(const Vector& x, const Vector& p, const Vector& dx, const Vector& dp, Vector& out_x,
                         Vector& out_p) const override {
    sum_->add_hessian_times(x, p, dx, dp, out_x, out_p);
  }
  bool is_least_squares() const override { return true; }
  int num_residuals() const override { return sum_->num_residuals(); }
  void residuals(const Vector& x, const Vector& p, Vector& r, SparseMatrix* dr_dx,
                 SparseMatrix* dr_dp) const override {
    sum_->residuals(x, p, r, dr_dx, dr_dp);
  }

  int num_handles() const { return static_cast<int>(handles_.size()); }
  const Handle& handle(int h) const { return handles_[static_cast<std::size_t>(h)]; }
  // The handle DOFs in u~ order (pass to Model::add_prescribed_displacements).
  const std::vector<int>& dofs() const { return dofs_; }
  int displacement_offset() const { return offset_; }
  int displacement_size() const { return static_cast<int>(dofs_.size()); }
  // ubar over the u~ block (0 where a handle has none) and the per-entry mask (1 where it has).
  const Vector& target_displacement() const { return ubar_; }
  const Vector& displacement_mask() const { return mask_; }
  // The total force handle h applies to the body (dim entries), whatever its target's form.
  Vector total_force(int h, const Vector& x, const Vector& p) const;
  // The force in the form of its target (total or per vertex); empty without a target.
  Vector force(int h, const Vector& x, const Vector& p) const;
  // u~ of handle h: |vertices| x dim.
  Matrix displacement(int h, const Vector& p) const;
  // Both parts of J at (x, p), alpha and beta included.
  double force_term(const Vector& x, const Vector& p) const;
  double displacement_term(const Vector& x, const Vector& p) const;

 private:
  std::vector<std::shared_ptr<const EnergyTerm>> terms_;
  int num_dofs_, dim_, offset_;
  HandleObjectiveOptions options_;
  std::vector<Handle> handles_;
  std::vector<int> dofs_, first_dof_;  // first_dof_[h]: start of handle h in u~
  Vector ubar_, mask_;
  std::vector<std::shared_ptr<const TargetReactionForces>> force_parts_;  // per handle; null without fbar
  std::shared_ptr<const Objective> displacement_part_;
  std::shared_ptr<WeightedSum> sum_;
};

}  // namespace tailor
