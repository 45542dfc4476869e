#include "objectives/target_dofs.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_set>

namespace tailor {

TargetDofs::TargetDofs(std::vector<int> dofs, Vector targets, double weight)
    : dofs_(std::move(dofs)), targets_(std::move(targets)), weight_(weight) {
  const std::string who = "TargetDofs: ";
  if (dofs_.empty()) throw std::invalid_argument(who + "no DOFs selected");
  if (targets_.size() != static_cast<Eigen::Index>(dofs_.size()))
    throw std::invalid_argument(who + std::to_string(dofs_.size()) + " DOFs but " + std::to_string(targets_.size()) +
                                " targets");
  std::unordered_set<int> seen;
  for (int d : dofs_) {
    if (d < 0) throw std::invalid_argument(who + "negative DOF index " + std::to_string(d));
    if (!seen.insert(d).second) throw std::invalid_argument(who + "DOF " + std::to_string(d) + " selected twice");
  }
  if (!targets_.allFinite()) throw std::invalid_argument(who + "targets are not finite");
  if (!std::isfinite(weight_) || weight_ < 0) throw std::invalid_argument(who + "the weight must be finite and >= 0");
  max_dof_ = *std::max_element(dofs_.begin(), dofs_.end());
}

void TargetDofs::check_state(const Vector& x) const {
  if (max_dof_ >= x.size())
    throw std::invalid_argument("TargetDofs: DOF " + std::to_string(max_dof_) + " is not in a state of " +
                                std::to_string(x.size()) + " entries");
}

double TargetDofs::value(const Vector& x, const Vector& p) const {
  (void)p;
  check_state(x);
  double J = 0.0;
  for (std::size_t i = 0; i < dofs_.size(); ++i) {
    const double r = x[dofs_[i]] - targets_[static_cast<Eigen::Index>(i)];
    J += r * r;
  }
  return 0.5 * weight_ * J;
}

// dJ/dx_{d_i} = w (x_{d_i} - t_i).
void TargetDofs::add_gradient_x(const Vector& x, const Vector& p, Vector& gx) const {
  (void)p;
  check_state(x);
  for (std::size_t i = 0; i < dofs_.size(); ++i)
    gx[dofs_[i]] += weight_ * (x[dofs_[i]] - targets_[static_cast<Eigen::Index>(i)]);
}

// J_xx = w on the selected entries; no p-dependence.
void TargetDofs::add_hessian_times(const Vector& x, const Vector& p, const Vector& dx, const Vector& dp,
                                   Vector& out_x, Vector& out_p) const {
  (void)p, (void)dp, (void)out_p;
  check_state(x);
  for (int d : dofs_) out_x[d] += weight_ * dx[d];
}

void TargetDofs::residuals(const Vector& x, const Vector& p, Vector& r, SparseMatrix* dr_dx,
                           SparseMatrix* dr_dp) const {
  check_state(x);
  const double s = std::sqrt(weight_);
  r.resize(num_residuals());
  for (std::size_t i = 0; i < dofs_.size(); ++i)
    r[static_cast<Eigen::Index>(i)] = s * (x[dofs_[i]] - targets_[static_cast<Eigen::Index>(i)]);
  if (dr_dx) {
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(dofs_.size());
    for (std::size_t i = 0; i < dofs_.size(); ++i) t.emplace_back(static_cast<int>(i), dofs_[i], s);
    dr_dx->resize(num_residuals(), x.size());
    dr_dx->setFromTriplets(t.begin(), t.end());
  }
  if (dr_dp) dr_dp->resize(num_residuals(), p.size());
}

}  // namespace tailor
