// Lagged IPC friction through rigid and deformable surfaces (see friction_term.hpp).
#include "forward/rigid/friction_term.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace tailor::rigid {

FrictionTerm::FrictionTerm(const RigidContactTerm& contact, contact::FrictionOptions options)
    : contact_(contact), options_(options) {
  if (!(options_.coefficient >= 0.0) || !std::isfinite(options_.coefficient))
    throw std::invalid_argument("friction: the coefficient must be >= 0, got " +
                                std::to_string(options_.coefficient));
  if (!(options_.velocity_threshold > 0.0) || !std::isfinite(options_.velocity_threshold))
    throw std::invalid_argument("friction: the velocity threshold eps_v must be positive, got " +
                                std::to_string(options_.velocity_threshold));
  contact_.bodies().add_pattern(slots_);
}

void FrictionTerm::hessian_pattern(HessianPattern& pattern) const {
  pattern.insert(pattern.end(), slots_.pattern().begin(), slots_.pattern().end());
}

void FrictionTerm::lag(const Vector& q_lag, const Vector& q_start, double time_step) {
  if (!(time_step > 0.0)) throw std::invalid_argument("friction: the time step must be positive");
  threshold_ = options_.velocity_threshold * time_step;
  pairs_.clear();
  if (options_.coefficient == 0.0) return;
  const ContactBodies& bodies = contact_.bodies();
  pairs_ =
      contact::lag_friction_pairs(contact_.potential(), bodies.positions(q_lag), bodies.positions(q_start));
}

Eigen::Matrix<double, 12, 1> FrictionTerm::stencil(const contact::Positions& x,
                                                   const std::array<int, 4>& v) const {
  Eigen::Matrix<double, 12, 1> s;
  for (int k = 0; k < 4; ++k) s.segment<3>(3 * k) = x.row(v[static_cast<std::size_t>(k)]).transpose();
  return s;
}

void FrictionTerm::evaluate(const Vector& q, const Vector& p, const EnergyRequest& request) const {
  (void)p;
  if (request.hessian_values) std::fill(request.hessian_values, request.hessian_values + slots_.size(), 0.0);
  if (pairs_.empty()) return;
  const bool derivatives = request.gradient || request.hessian_values;
  const ContactBodies& bodies = contact_.bodies();
  const contact::Positions x = bodies.positions(q);
  const std::vector<RotationDerivatives> rotations =
      derivatives ? bodies.rotations(q) : std::vector<RotationDerivatives>();
  double energy = 0.0;
  for (const contact::FrictionPair& pair : pairs_) {
    const contact::FrictionDerivatives d = contact::friction_pair_potential(
        pair, stencil(x, pair.vertices), options_.coefficient, threshold_, derivatives);
    energy += d.value;
    if (derivatives) bodies.add_stencil(pair.vertices, d.gradient, d.hessian, rotations, slots_, request);
  }
  if (request.value) *request.value += energy;
}

std::pair<int, int> FrictionTerm::sliding_and_sticking(const Vector& q) const {
  const contact::Positions x = contact_.bodies().positions(q);
  int sliding = 0, sticking = 0;
  for (const contact::FrictionPair& pair : pairs_) {
    const double slip = (pair.tangent * (stencil(x, pair.vertices) - pair.start)).norm();
    (slip >= threshold_ ? sliding : sticking)++;
  }
  return {sliding, sticking};
}

}  // namespace tailor::rigid
