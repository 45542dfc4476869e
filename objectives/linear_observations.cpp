#include "objectives/linear_observations.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace tailor {

LinearObservations::LinearObservations(SparseMatrix observations, Vector targets, Vector weights)
    : observations_(std::move(observations)), targets_(std::move(targets)), weights_(std::move(weights)) {
  const std::string who = "LinearObservations: ";
  if (observations_.rows() == 0) throw std::invalid_argument(who + "no observations");
  if (targets_.size() != observations_.rows() || weights_.size() != observations_.rows())
    throw std::invalid_argument(who + std::to_string(observations_.rows()) + " observations but " +
                                std::to_string(targets_.size()) + " targets and " + std::to_string(weights_.size()) +
                                " weights");
  for (int k = 0; k < observations_.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(observations_, k); it; ++it)
      if (!std::isfinite(it.value())) throw std::invalid_argument(who + "the observation matrix is not finite");
  if (!targets_.allFinite()) throw std::invalid_argument(who + "targets are not finite");
  if (!weights_.allFinite() || (weights_.array() < 0.0).any())
    throw std::invalid_argument(who + "the weights must be finite and >= 0");
  observations_.makeCompressed();
}

void LinearObservations::check_state(const Vector& x) const {
  if (x.size() != observations_.cols())
    throw std::invalid_argument("LinearObservations: a state of " + std::to_string(x.size()) +
                                " entries; the observations read " + std::to_string(observations_.cols()));
}

Vector LinearObservations::misfit(const Vector& x) const {
  check_state(x);
  return observations_ * x - targets_;
}

double LinearObservations::value(const Vector& x, const Vector& p) const {
  (void)p;
  return 0.5 * (weights_.array() * misfit(x).array().square()).sum();
}

// dJ/dx = B^T C (B x - t).
void LinearObservations::add_gradient_x(const Vector& x, const Vector& p, Vector& gx) const {
  (void)p;
  gx.noalias() += observations_.transpose() * weights_.cwiseProduct(misfit(x));
}

// J_xx = B^T C B; no p-dependence.
void LinearObservations::add_hessian_times(const Vector& x, const Vector& p, const Vector& dx, const Vector& dp,
                                           Vector& out_x, Vector& out_p) const {
  (void)p, (void)dp, (void)out_p;
  check_state(x);
  out_x.noalias() += observations_.transpose() * weights_.cwiseProduct(observations_ * dx);
}

void LinearObservations::residuals(const Vector& x, const Vector& p, Vector& r, SparseMatrix* dr_dx,
                                   SparseMatrix* dr_dp) const {
  const Vector root = weights_.cwiseSqrt();
  r = root.cwiseProduct(misfit(x));
  if (dr_dx) *dr_dx = root.asDiagonal() * observations_;
  if (dr_dp) dr_dp->resize(num_residuals(), p.size());
}

}  // namespace tailor
