// Constant forces and torques on rigid bodies (see rigid_load_term.hpp).
#include "forward/rigid/rigid_load_term.hpp"

#include <stdexcept>
#include <string>

#include "forward/core/psd_projection.hpp"
#include "forward/rigid/rotation.hpp"

namespace tailor::rigid {

RigidLoadTerm::RigidLoadTerm(Vector loads, Vector reference) : reference_(std::move(reference)) {
  if (reference_.size() % 6 != 0)
    throw std::invalid_argument("RigidLoadTerm: " + std::to_string(reference_.size()) +
                                " reference DOFs, expected 6 per body");
  set_loads(std::move(loads));
  set_reference(reference_);
}

void RigidLoadTerm::set_loads(Vector loads) {
  if (loads.size() != reference_.size())
    throw std::invalid_argument("RigidLoadTerm: " + std::to_string(loads.size()) + " loads for " +
                                std::to_string(reference_.size()) + " DOFs");
  loads_ = std::move(loads);
}

void RigidLoadTerm::set_reference(const Vector& q) {
  if (q.size() != reference_.size())
    throw std::invalid_argument("RigidLoadTerm: reference state of size " + std::to_string(q.size()) +
                                ", expected " + std::to_string(reference_.size()));
  reference_rotation_.clear();
  for (Eigen::Index b = 0; b < q.size() / 6; ++b)
    reference_rotation_.push_back(rotation_matrix(q.segment<3>(6 * b + 3)));
}

bool RigidLoadTerm::has_torques() const {
  for (Eigen::Index b = 0; b < loads_.size() / 6; ++b)
    if (loads_.segment<3>(6 * b + 3).squaredNorm() > 0.0) return true;
  return false;
}

void RigidLoadTerm::hessian_pattern(HessianPattern& pattern) const {
  for (int b = 0; b < static_cast<int>(loads_.size() / 6); ++b)
    for (int k = 3; k < 6; ++k)
      for (int l = 3; l < 6; ++l) pattern.push_back({6 * b + k, 6 * b + l});
}

void RigidLoadTerm::evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const {
  (void)p;
  double* slot = request.hessian_values;
  for (Eigen::Index b = 0; b < loads_.size() / 6; ++b) {
    const Eigen::Vector3d f = loads_.segment<3>(6 * b), tau = loads_.segment<3>(6 * b + 3);
    const Eigen::Matrix3d& Rb = reference_rotation_[static_cast<std::size_t>(b)];
    if (request.value) *request.value -= f.dot(x.segment<3>(6 * b) - reference_.segment<3>(6 * b));
    if (request.gradient) request.gradient->segment<3>(6 * b) -= f;
    const bool torque = tau.squaredNorm() > 0.0;
    if (!torque) {
      if (slot) slot = std::fill_n(slot, 9, 0.0);
      continue;
    }
    if (!request.gradient && !slot) {
      if (request.value)
        *request.value -= tau.dot(skew_vee(rotation_matrix(x.segment<3>(6 * b + 3)) * Rb.transpose()));
      continue;
    }
    const RotationDerivatives r = rotation_derivatives(x.segment<3>(6 * b + 3));
    if (request.value) *request.value -= tau.dot(skew_vee(r.rotation * Rb.transpose()));
    if (request.gradient)
      for (int k = 0; k < 3; ++k)
        (*request.gradient)[6 * b + 3 + k] -=
            tau.dot(skew_vee(r.first[static_cast<std::size_t>(k)] * Rb.transpose()));
    if (!slot) continue;
    Eigen::Matrix3d H;
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 3; ++l)
        H(k, l) = -tau.dot(
            skew_vee(r.second[static_cast<std::size_t>(k)][static_cast<std::size_t>(l)] * Rb.transpose()));
    if (request.hessian_mode == HessianMode::projected) project_psd(H);
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 3; ++l) *slot++ = H(k, l);
  }
}

}  // namespace tailor::rigid
