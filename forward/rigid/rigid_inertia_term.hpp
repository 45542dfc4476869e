#pragma once
// The inertia part of the implicit Euler incremental potential of rigid bodies (docs/methods.md
// section 1; rigid IPC, Ferguson et al. 2021, with the orientation as a matrix): for a step h,
//   E(q) = sum_b  m_b / (2 h^2) |T_b - T~_b|^2
//               + 1 / (2 h^2) tr( (R(w_b) - Q~_b) J_b (R(w_b) - Q~_b)^T )      [energy],
// T~ = T_n + h v_n and Q~ = R_n + h Rdot_n the predictions, J_b = integral of rho V V^T over
// the body (= tr(I)/2 Id - I, I the inertia about the centre, body frame). Derivatives in w
// through rotation.hpp: dE/dw_k = tr(dR_k J (R - Q~)^T) / h^2 and
//   d2E/dw_k dw_l = ( tr(d2R_kl J (R - Q~)^T) + tr(dR_k J dR_l^T) ) / h^2.
// Gravity, loads and contact are separate terms; RigidTimeStepper advances the motion.
#include <vector>

#include "forward/core/energy_term.hpp"
#include "forward/rigid/rigid_body_system.hpp"

namespace tailor::rigid {

// The motion of one body at a time step.
struct RigidMotion {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();       // T [length]
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();       // dT/dt [length / time]
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();   // R
  Eigen::Matrix3d rotation_rate = Eigen::Matrix3d::Zero();  // dR/dt [1 / time]
};

class RigidInertiaTerm final : public EnergyTerm {
 public:
  // Throws std::invalid_argument for a non-positive time step.
  RigidInertiaTerm(const RigidBodySystem& system, double time_step);
  std::string name() const override { return "rigid_inertia"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;

  // Sets the predictions T~, Q~ from the motion at the start of the step (one per body).
  void predict(const std::vector<RigidMotion>& motion);
  double time_step() const { return h_; }
  // J_b = tr(I)/2 Id - I of body b.
  const Eigen::Matrix3d& second_moment(int b) const { return second_moments_[static_cast<std::size_t>(b)]; }

 private:
  const RigidBodySystem& system_;
  double h_;
  std::vector<Eigen::Matrix3d> second_moments_, predicted_rotation_;
  std::vector<Eigen::Vector3d> predicted_position_;
};

}  // namespace tailor::rigid
