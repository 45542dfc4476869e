// Implicit Euler steps of rigid bodies (see rigid_time_stepper.hpp).
#include "forward/rigid/rigid_time_stepper.hpp"

#include <cmath>

namespace tailor::rigid {

RigidTimeStepper::RigidTimeStepper(const RigidBodySystem& system, Model& model, RigidInertiaTerm& inertia,
                                   NewtonOptions options)
    : system_(system), model_(model), inertia_(inertia), newton_(model, options), q_(system.initial_state()) {
  for (int b = 0; b < system.num_bodies(); ++b) {
    RigidMotion m;
    m.position = system.body(b).position;
    m.rotation = rotation_matrix(system.body(b).rotation);
    motion_.push_back(m);
  }
}

void RigidTimeStepper::set_velocity(int body, const Eigen::Vector3d& velocity,
                                    const Eigen::Vector3d& angular_velocity) {
  RigidMotion& m = motion_[static_cast<std::size_t>(body)];
  m.velocity = velocity;
  Eigen::Matrix3d W;  // dR/dt = [omega] R (omega in world coordinates)
  W << 0, -angular_velocity.z(), angular_velocity.y(), angular_velocity.z(), 0, -angular_velocity.x(),
      -angular_velocity.y(), angular_velocity.x(), 0;
  m.rotation_rate = W * m.rotation;
}

NewtonResult RigidTimeStepper::step() {
  inertia_.predict(motion_);
  Vector y = model_.elimination().restrict_state(q_);
  const NewtonResult result = newton_.solve(Vector(), y);
  if (!result.converged()) return result;
  q_ = model_.state(y, Vector());
  const double h = inertia_.time_step();
  for (int b = 0; b < system_.num_bodies(); ++b) {
    RigidMotion& m = motion_[static_cast<std::size_t>(b)];
    const Eigen::Vector3d T = q_.segment<3>(6 * b);
    const Eigen::Matrix3d R = rotation_matrix(q_.segment<3>(6 * b + 3));
    m.velocity = (T - m.position) / h;
    m.rotation_rate = (R - m.rotation) / h;
    m.position = T;
    m.rotation = R;
    Eigen::Vector3d w = q_.segment<3>(6 * b + 3);
    const double angle = w.norm();
    if (angle > M_PI) q_.segment<3>(6 * b + 3) = w * (1.0 - 2.0 * M_PI / angle);  // the same rotation
  }
  return result;
}

}  // namespace tailor::rigid
