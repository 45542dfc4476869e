// Rigid-body inertia of the implicit Euler incremental potential (see rigid_inertia_term.hpp).
#include "forward/rigid/rigid_inertia_term.hpp"

#include <stdexcept>
#include <string>

#include "forward/core/psd_projection.hpp"

namespace tailor::rigid {

RigidInertiaTerm::RigidInertiaTerm(const RigidBodySystem& system, double time_step)
    : system_(system), h_(time_step) {
  if (!(time_step > 0.0)) throw std::invalid_argument("RigidInertiaTerm: time step must be positive");
  std::vector<RigidMotion> rest(static_cast<std::size_t>(system.num_bodies()));
  for (int b = 0; b < system.num_bodies(); ++b) {
    const Eigen::Matrix3d& I = system.body(b).inertia;
    second_moments_.push_back(0.5 * I.trace() * Eigen::Matrix3d::Identity() - I);
    rest[static_cast<std::size_t>(b)].position = system.body(b).position;
    rest[static_cast<std::size_t>(b)].rotation = rotation_matrix(system.body(b).rotation);
  }
  predict(rest);
}

void RigidInertiaTerm::predict(const std::vector<RigidMotion>& motion) {
  if (static_cast<int>(motion.size()) != system_.num_bodies())
    throw std::invalid_argument("RigidInertiaTerm: motion of " + std::to_string(motion.size()) +
                                " bodies for " + std::to_string(system_.num_bodies()));
  predicted_position_.clear();
  predicted_rotation_.clear();
  for (const RigidMotion& m : motion) {
    predicted_position_.push_back(m.position + h_ * m.velocity);
    predicted_rotation_.push_back(m.rotation + h_ * m.rotation_rate);
  }
}

void RigidInertiaTerm::hessian_pattern(HessianPattern& pattern) const {
  for (int b = 0; b < system_.num_bodies(); ++b) {
    for (int k = 0; k < 3; ++k) pattern.push_back({6 * b + k, 6 * b + k});
    for (int k = 3; k < 6; ++k)
      for (int l = 3; l < 6; ++l) pattern.push_back({6 * b + k, 6 * b + l});
  }
}

void RigidInertiaTerm::evaluate(const Vector& q, const Vector& p, const EnergyRequest& request) const {
  (void)p;
  const double scale = 1.0 / (h_ * h_);
  double* slot = request.hessian_values;
  for (int b = 0; b < system_.num_bodies(); ++b) {
    const std::size_t i = static_cast<std::size_t>(b);
    const double m = system_.body(b).mass;
    const Eigen::Vector3d dT = q.segment<3>(6 * b) - predicted_position_[i];
    const Eigen::Matrix3d& J = second_moments_[i];
    const bool rotation_derivatives_needed = request.gradient || slot;
    if (!rotation_derivatives_needed) {
      const Eigen::Matrix3d D = rotation_matrix(q.segment<3>(6 * b + 3)) - predicted_rotation_[i];
      if (request.value)
        *request.value += 0.5 * scale * (m * dT.squaredNorm() + (D * J * D.transpose()).trace());
      continue;
    }
    const RotationDerivatives r = rotation_derivatives(q.segment<3>(6 * b + 3));
    const Eigen::Matrix3d D = r.rotation - predicted_rotation_[i];
    const Eigen::Matrix3d DJ = D * J;
    if (request.value) *request.value += 0.5 * scale * (m * dT.squaredNorm() + (DJ * D.transpose()).trace());
    if (request.gradient) {
      request.gradient->segment<3>(6 * b) += scale * m * dT;
      for (int k = 0; k < 3; ++k)
        (*request.gradient)[6 * b + 3 + k] += scale * r.first[k].cwiseProduct(DJ).sum();
    }
    if (!slot) continue;
    for (int k = 0; k < 3; ++k) *slot++ = scale * m;
    Eigen::Matrix3d H;
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 3; ++l)
        H(k, l) = scale *
                  (r.second[k][l].cwiseProduct(DJ).sum() + (r.first[k] * J * r.first[l].transpose()).trace());
    if (request.hessian_mode == HessianMode::projected) project_psd(H);
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 3; ++l) *slot++ = H(k, l);
  }
}

}  // namespace tailor::rigid
