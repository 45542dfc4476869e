#include "objectives/handle_objective.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_set>

#include "objectives/tikhonov.hpp"

namespace tailor {

HandleObjective::HandleObjective(std::vector<std::shared_ptr<const EnergyTerm>> reaction_terms, int num_dofs,
                                 int dim, std::vector<Handle> handles, int displacement_offset,
                                 HandleObjectiveOptions options)
    : terms_(std::move(reaction_terms)),
      num_dofs_(num_dofs),
      dim_(dim),
      offset_(displacement_offset),
      options_(options),
      handles_(std::move(handles)) {
  const std::string who = "HandleObjective: ";
  if (handles_.empty()) throw std::invalid_argument(who + "no handles");
  if (dim_ < 1 || num_dofs_ < 1 || num_dofs_ % dim_ != 0)
    throw std::invalid_argument(who + "invalid number of DOFs " + std::to_string(num_dofs_) + " for dim " +
                                std::to_string(dim_));
  if (offset_ < 0) throw std::invalid_argument(who + "negative displacement offset");
  if (!std::isfinite(options_.alpha) || options_.alpha < 0 || !std::isfinite(options_.beta) ||
      options_.beta < 0)
    throw std::invalid_argument(who + "alpha and beta must be finite and >= 0");
  const int num_vertices = num_dofs_ / dim_;
  std::unordered_set<int> seen;
  std::vector<double> ubar, mask;
  for (std::size_t h = 0; h < handles_.size(); ++h) {
    const Handle& handle = handles_[h];
    const std::string which = who + "handle " + std::to_string(h) + ": ";
    const int n = static_cast<int>(handle.vertices.size());
    if (n == 0) throw std::invalid_argument(which + "no vertices");
    const bool has_u = handle.target_displacement.size() > 0, has_f = handle.target_force.size() > 0;
    if (!has_u && !has_f)
      throw std::invalid_argument(which + "neither a target displacement nor a target force");
    if (has_u && (handle.target_displacement.cols() != dim_ ||
                  (handle.target_displacement.rows() != 1 && handle.target_displacement.rows() != n)))
      throw std::invalid_argument(which + "target displacement must be 1 x " + std::to_string(dim_) + " or " +
                                  std::to_string(n) + " x " + std::to_string(dim_));
    if (has_u && !handle.target_displacement.allFinite())
      throw std::invalid_argument(which + "target displacement is not finite");
    if (has_f && handle.target_force.size() != dim_ && handle.target_force.size() != dim_ * n)
      throw std::invalid_argument(which + "target force must have " + std::to_string(dim_) + " (total) or " +
                                  std::to_string(dim_ * n) + " (per vertex) entries, got " +
                                  std::to_string(handle.target_force.size()));
    if (!std::isfinite(handle.weight) || handle.weight < 0)
      throw std::invalid_argument(which + "weight must be finite and >= 0");
    first_dof_.push_back(static_cast<int>(dofs_.size()));
    std::vector<int> handle_dofs;
    for (int i = 0; i < n; ++i) {
      const int v = handle.vertices[static_cast<std::size_t>(i)];
      if (v < 0 || v >= num_vertices)
        throw std::invalid_argument(which + "vertex " + std::to_string(v) + " out of range [0, " +
                                    std::to_string(num_vertices) + ")");
      if (!seen.insert(v).second)
        throw std::invalid_argument(which + "vertex " + std::to_string(v) +
                                    " is in two handles or twice in one");
      for (int k = 0; k < dim_; ++k) {
        handle_dofs.push_back(dim_ * v + k);
        ubar.push_back(has_u ? handle.target_displacement(handle.target_displacement.rows() == 1 ? 0 : i, k)
                             : 0.0);
        mask.push_back(has_u ? 1.0 : 0.0);
      }
    }
    dofs_.insert(dofs_.end(), handle_dofs.begin(), handle_dofs.end());
    if (has_f) {
      const bool total = handle.target_force.size() == dim_;
      force_parts_.push_back(std::make_shared<TargetReactionForces>(
          terms_, num_dofs_, dim_, handle_dofs,
          total ? TargetReactionForces::Aggregation::total : TargetReactionForces::Aggregation::per_dof,
          handle.target_force, Vector::Constant(handle.target_force.size(), handle.weight)));
    } else {
      force_parts_.push_back(nullptr);
    }
  }
  ubar_ = Eigen::Map<const Vector>(ubar.data(), static_cast<Eigen::Index>(ubar.size()));
  mask_ = Eigen::Map<const Vector>(mask.data(), static_cast<Eigen::Index>(mask.size()));

  std::vector<ObjectivePtr> parts;
  std::vector<double> coefficients;
  for (const auto& part : force_parts_)
    if (part) {
      parts.push_back(part);
      coefficients.push_back(options_.alpha);
    }
  // alpha beta/2 |u~ - ubar|^2 on the handles that have a ubar (Tikhonov weight 1, else 0).
  displacement_part_ =
      std::make_shared<Tikhonov>(offset_, displacement_size(), options_.alpha * options_.beta, ubar_, mask_);
  parts.push_back(displacement_part_);
  coefficients.push_back(1.0);
  sum_ = std::make_shared<WeightedSum>(std::move(parts), std::move(coefficients));
}

Vector HandleObjective::total_force(int h, const Vector& x, const Vector& p) const {
  Vector f = Vector::Zero(num_dofs_);
  for (const auto& term : terms_) term->add_gradient(x, p, f);
  Vector total = Vector::Zero(dim_);
  for (int v : handle(h).vertices) total += f.segment(dim_ * v, dim_);
  return total;
}

Vector HandleObjective::force(int h, const Vector& x, const Vector& p) const {
  const auto& part = force_parts_[static_cast<std::size_t>(h)];
  return part ? part->reaction(x, p) : Vector();
}

Matrix HandleObjective::displacement(int h, const Vector& p) const {
  const int n = static_cast<int>(handle(h).vertices.size());
  if (p.size() < offset_ + displacement_size())
    throw std::invalid_argument(
        "HandleObjective: the parameter vector does not hold the handle displacements");
  Matrix u(n, dim_);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < dim_; ++k)
      u(i, k) = p[offset_ + first_dof_[static_cast<std::size_t>(h)] + dim_ * i + k];
  return u;
}

double HandleObjective::force_term(const Vector& x, const Vector& p) const {
  double value = 0.0;
  for (const auto& part : force_parts_)
    if (part) value += options_.alpha * part->value(x, p);
  return value;
}

double HandleObjective::displacement_term(const Vector& x, const Vector& p) const {
  return displacement_part_->value(x, p);
}

}  // namespace tailor
