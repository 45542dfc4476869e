// Gravity on rigid bodies (see rigid_gravity_term.hpp).
#include "forward/rigid/rigid_gravity_term.hpp"

namespace tailor::rigid {

RigidGravityTerm::RigidGravityTerm(const RigidBodySystem& system, const Eigen::Vector3d& gravity,
                                   int mass_offset)
    : gravity_(gravity),
      mass_offset_(mass_offset),
      masses_(system.num_bodies()),
      initial_(system.initial_state()) {
  for (int b = 0; b < system.num_bodies(); ++b) masses_[b] = system.body(b).mass;
}

double RigidGravityTerm::mass(const Vector& p, int b) const {
  return mass_offset_ >= 0 ? p[mass_offset_ + b] : masses_[b];
}

void RigidGravityTerm::evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const {
  for (int b = 0; b < masses_.size(); ++b) {
    const double m = mass(p, b);
    if (request.value) *request.value -= m * gravity_.dot(x.segment<3>(6 * b) - initial_.segment<3>(6 * b));
    if (request.gradient) request.gradient->segment<3>(6 * b) -= m * gravity_;
  }
}

void RigidGravityTerm::add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const {
  (void)p;
  if (mass_offset_ < 0) return;
  for (int b = 0; b < masses_.size(); ++b)
    gradient_p[mass_offset_ + b] -= gravity_.dot(x.segment<3>(6 * b) - initial_.segment<3>(6 * b));
}

void RigidGravityTerm::add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const {
  (void)x, (void)p;
  if (mass_offset_ < 0) return;
  for (int b = 0; b < masses_.size(); ++b)
    for (int k = 0; k < 3; ++k) mixed.emplace_back(6 * b + k, mass_offset_ + b, -gravity_[k]);
}

}  // namespace tailor::rigid
