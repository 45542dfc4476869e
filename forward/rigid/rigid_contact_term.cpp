// The IPC barrier between rigid bodies and deformable surfaces (see rigid_contact_term.hpp).
#include "forward/rigid/rigid_contact_term.hpp"

#include <algorithm>

namespace tailor::rigid {

RigidContactTerm::RigidContactTerm(const RigidBodySystem& system, contact::ContactOptions options)
    : RigidContactTerm(std::make_shared<const ContactBodies>(system), system.initial_state(), options) {}

RigidContactTerm::RigidContactTerm(std::shared_ptr<const ContactBodies> bodies, const Vector& rest_state,
                                   contact::ContactOptions options)
    : bodies_(std::move(bodies)), potential_(bodies_->surface(), bodies_->positions(rest_state), options) {
  bodies_->add_pattern(slots_);
}

void RigidContactTerm::hessian_pattern(HessianPattern& pattern) const {
  pattern.insert(pattern.end(), slots_.pattern().begin(), slots_.pattern().end());
}

void RigidContactTerm::evaluate(const Vector& q, const Vector& p, const EnergyRequest& request) const {
  (void)p;
  if (request.hessian_values) std::fill(request.hessian_values, request.hessian_values + slots_.size(), 0.0);
  const bool derivatives = request.gradient || request.hessian_values;
  if (!request.value && !derivatives) return;
  const contact::Positions x = bodies_->positions(q);
  const std::vector<RotationDerivatives> rotations =
      derivatives ? bodies_->rotations(q) : std::vector<RotationDerivatives>();
  double energy = 0.0;
  potential_.for_each_active(x, derivatives, [&](const contact::ActivePair& pair) {
    energy += pair.derivatives.value;
    if (derivatives)
      bodies_->add_stencil(pair.vertices, pair.derivatives.gradient, pair.derivatives.hessian, rotations,
                           slots_, request);
  });
  if (request.value) *request.value += energy;
}

double RigidContactTerm::max_step(const Vector& q, const Vector& dq) const {
  return bodies_->max_step(q, dq, potential_);
}

double RigidContactTerm::min_distance(const Vector& q, double range) const {
  return potential_.min_distance(bodies_->positions(q), range);
}

Vector RigidContactTerm::unit_stiffness_gradient(const Vector& q) const {
  Vector gradient = Vector::Zero(q.size());
  const std::vector<RotationDerivatives> rotations = bodies_->rotations(q);
  const double kappa = potential_.options().stiffness;
  potential_.for_each_active(bodies_->positions(q), true, [&](const contact::ActivePair& pair) {
    bodies_->add_stencil_gradient(pair.vertices, pair.derivatives.gradient / kappa, rotations, gradient);
  });
  return gradient;
}

contact::Positions RigidContactTerm::vertex_forces(const Vector& q) const {
  contact::Positions forces = contact::Positions::Zero(bodies_->surface().num_vertices, 3);
  potential_.for_each_active(bodies_->positions(q), true, [&](const contact::ActivePair& pair) {
    for (int k = 0; k < 4; ++k)
      forces.row(pair.vertices[static_cast<std::size_t>(k)]) -=
          pair.derivatives.gradient.segment<3>(3 * k).transpose();
  });
  return forces;
}

}  // namespace tailor::rigid
