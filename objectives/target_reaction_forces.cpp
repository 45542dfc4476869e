#include "objectives/target_reaction_forces.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_set>

namespace tailor {
namespace {

const EnergyTerm& non_null(const std::shared_ptr<const EnergyTerm>& term) {
  if (!term) throw std::invalid_argument("TargetReactionForces: energy term is null");
  return *term;
}

}  // namespace

TargetReactionForces::TargetReactionForces(const EnergyTerm& term, int num_dofs, int dim,
                                           std::vector<int> dofs, Aggregation aggregation, Vector target,
                                           Vector weights)
    : terms_{&term}, num_dofs_(num_dofs), target_(std::move(target)), weights_(std::move(weights)) {
  initialize(dim, dofs, aggregation);
}

TargetReactionForces::TargetReactionForces(std::shared_ptr<const EnergyTerm> term, int num_dofs, int dim,
                                           std::vector<int> dofs, Aggregation aggregation, Vector target,
                                           Vector weights)
    : TargetReactionForces(non_null(term), num_dofs, dim, std::move(dofs), aggregation, std::move(target),
                           std::move(weights)) {
  owners_.push_back(std::move(term));
}

TargetReactionForces::TargetReactionForces(std::vector<std::shared_ptr<const EnergyTerm>> terms, int num_dofs,
                                           int dim, std::vector<int> dofs, Aggregation aggregation,
                                           Vector target, Vector weights)
    : owners_(std::move(terms)),
      num_dofs_(num_dofs),
      target_(std::move(target)),
      weights_(std::move(weights)) {
  if (owners_.empty()) throw std::invalid_argument("TargetReactionForces: no energy terms");
  for (const auto& term : owners_) terms_.push_back(&non_null(term));
  initialize(dim, dofs, aggregation);
}

void TargetReactionForces::initialize(int dim, const std::vector<int>& dofs, Aggregation aggregation) {
  const std::string who = "TargetReactionForces: ";
  if (num_dofs_ < 1) throw std::invalid_argument(who + "number of DOFs must be positive");
  if (dim < 1) throw std::invalid_argument(who + "dim must be positive, got " + std::to_string(dim));
  if (num_dofs_ % dim != 0)
    throw std::invalid_argument(who + "number of DOFs " + std::to_string(num_dofs_) +
                                " is not a multiple of dim " + std::to_string(dim));
  if (dofs.empty()) throw std::invalid_argument(who + "no DOFs selected");
  std::unordered_set<int> seen;
  for (int d : dofs) {
    if (d < 0 || d >= num_dofs_)
      throw std::invalid_argument(who + "DOF " + std::to_string(d) + " out of range [0, " +
                                  std::to_string(num_dofs_) + ")");
    if (!seen.insert(d).second)
      throw std::invalid_argument(who + "DOF " + std::to_string(d) + " selected twice");
  }
  const int m = aggregation == Aggregation::per_dof ? static_cast<int>(dofs.size()) : dim;
  Triplets triplets;
  for (std::size_t i = 0; i < dofs.size(); ++i)
    triplets.emplace_back(aggregation == Aggregation::per_dof ? static_cast<int>(i) : dofs[i] % dim, dofs[i],
                          1.0);
  selection_.resize(m, num_dofs_);
  selection_.setFromTriplets(triplets.begin(), triplets.end());

  if (target_.size() != m)
    throw std::invalid_argument(who + "target has " + std::to_string(target_.size()) + " entries, expected " +
                                std::to_string(m));
  if (!target_.allFinite()) throw std::invalid_argument(who + "target is not finite");
  if (weights_.size() == 0) weights_ = Vector::Ones(m);
  if (weights_.size() != m)
    throw std::invalid_argument(who + "weights have " + std::to_string(weights_.size()) +
                                " entries, expected " + std::to_string(m));
  for (int i = 0; i < m; ++i)
    if (!std::isfinite(weights_[i]) || weights_[i] < 0)
      throw std::invalid_argument(who + "weight " + std::to_string(i) + " must be finite and >= 0");
}

std::string TargetReactionForces::name() const {
  std::string names;
  for (const EnergyTerm* term : terms_) names += (names.empty() ? "" : " + ") + term->name();
  return "target_reaction_forces(" + names + ")";
}

void TargetReactionForces::check_state(const Vector& x) const {
  if (x.size() != num_dofs_)
    throw std::invalid_argument("TargetReactionForces: state has " + std::to_string(x.size()) +
                                " DOFs, expected " + std::to_string(num_dofs_));
}

Vector TargetReactionForces::reaction(const Vector& x, const Vector& p) const {
  check_state(x);
  Vector f = Vector::Zero(num_dofs_);
  for (const EnergyTerm* term : terms_) term->add_gradient(x, p, f);
  return selection_ * f;
}

Vector TargetReactionForces::weighted_misfit(const Vector& x, const Vector& p) const {
  return weights_.cwiseProduct(reaction(x, p) - target_);
}

double TargetReactionForces::value(const Vector& x, const Vector& p) const {
  const Vector e = reaction(x, p) - target_;
  return 0.5 * e.dot(weights_.cwiseProduct(e));
}

// dJ/dx = H^T A^T W (A f - y*) = H A^T W (A f - y*): the exact Hessian of an energy is
// symmetric, so one Hessian-vector product per term, without assembling H.
void TargetReactionForces::add_gradient_x(const Vector& x, const Vector& p, Vector& gx) const {
  const Vector adjoint = selection_.transpose() * weighted_misfit(x, p);
  for (const EnergyTerm* term : terms_) term->add_hessian_times(x, p, adjoint, gx, HessianMode::exact);
}

// dJ/dp = M^T A^T W (A f - y*), M = d2E/dxdp (n x |p|).
void TargetReactionForces::add_gradient_p(const Vector& x, const Vector& p, Vector& gp) const {
  const Vector adjoint = selection_.transpose() * weighted_misfit(x, p);
  for (const EnergyTerm* term : terms_) term->add_mixed_transpose_times(x, p, adjoint, gp);
}

void TargetReactionForces::add_hessian_times(const Vector& x, const Vector& p, const Vector& dx,
                                             const Vector& dp, Vector& out_x, Vector& out_p) const {
  (void)x, (void)p, (void)dx, (void)dp, (void)out_x, (void)out_p;
  throw std::logic_error(
      "TargetReactionForces: second derivatives need third derivatives of the energy, which are not "
      "available; "
      "use the least-squares (Gauss-Newton) form");
}

void TargetReactionForces::residuals(const Vector& x, const Vector& p, Vector& r, SparseMatrix* dr_dx,
                                     SparseMatrix* dr_dp) const {
  const Vector sqrt_w = weights_.cwiseSqrt();
  r = sqrt_w.cwiseProduct(reaction(x, p) - target_);
  const SparseMatrix scaled = sqrt_w.asDiagonal() * selection_;  // W^{1/2} A
  if (dr_dx) {
    SparseMatrix H(num_dofs_, num_dofs_);
    for (const EnergyTerm* term : terms_) H += term->hessian(x, p, HessianMode::exact);
    *dr_dx = scaled * H;
  }
  if (dr_dp) {
    Triplets mixed;
    for (const EnergyTerm* term : terms_) term->add_mixed(x, p, mixed);
    SparseMatrix M(num_dofs_, p.size());
    M.setFromTriplets(mixed.begin(), mixed.end());
    *dr_dp = scaled * M;
  }
}

}  // namespace tailor
