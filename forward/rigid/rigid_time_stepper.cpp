// Implicit Euler steps of rigid bodies (see rigid_time_stepper.hpp).
#include "forward/rigid/rigid_time_stepper.hpp"

#include <cmath>
#include <limits>

#include "forward/rigid/rotation.hpp"

namespace tailor::rigid {

RigidTimeStepper::RigidTimeStepper(const RigidBodySystem& system, Model& model, RigidInertiaTerm& inertia,
                                   NewtonOptions options, RigidStepOptions step_options)
    : system_(system),
      model_(model),
      inertia_(inertia),
      options_(std::move(options)),
      step_options_(step_options),
      newton_(model, options_),
      q_(system.initial_state()) {
  for (int b = 0; b < system.num_bodies(); ++b) {
    RigidMotion m;
    m.position = system.body(b).position;
    m.rotation = rotation_matrix(system.body(b).rotation);
    m.velocity = system.body(b).kinematic ? system.body(b).kinematic_velocity : Eigen::Vector3d::Zero();
    motion_.push_back(m);
  }
  if (step_options_.contact) {
    contact::ContactPotential& potential = step_options_.contact->potential();
    contact::StiffnessOptions& s = step_options_.stiffness;
    if (!(s.min_stiffness > 0.0)) s.min_stiffness = potential.options().stiffness;
    if (!(s.max_stiffness > 0.0)) s.max_stiffness = 100.0 * s.min_stiffness;
    if (s.adaptive) potential.set_stiffness(s.min_stiffness);
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

double RigidTimeStepper::distance_threshold() const {
  return step_options_.stiffness.distance_fraction *
         step_options_.contact->potential().options().activation_distance;
}

Vector RigidTimeStepper::predicted_state() const {
  Vector q = q_;
  const double h = inertia_.time_step();
  for (int b = 0; b < system_.num_bodies(); ++b) {
    if (system_.body(b).fixed || system_.body(b).kinematic) continue;
    const RigidMotion& m = motion_[static_cast<std::size_t>(b)];
    q.segment<3>(6 * b) = m.position + h * m.velocity;
    const Eigen::Vector3d omega = skew_vee(m.rotation_rate * m.rotation.transpose());
    q.segment<3>(6 * b + 3) =
        rotation_vector(rotation_matrix(h * omega) * m.rotation, q_.segment<3>(6 * b + 3));
  }
  return q;
}

NewtonResult RigidTimeStepper::solve(Vector& q) {
  NewtonOptions& o = newton_.options();
  o = options_;
  RigidContactTerm* contact = step_options_.contact;
  const double h = inertia_.time_step();
  if (step_options_.velocity_tolerance > 0.0) {
    std::vector<double> radius;  // largest |V| of each body
    for (const RigidBody& body : system_.bodies())
      radius.push_back(body.vertices.rowwise().norm().maxCoeff());
    const double limit = step_options_.velocity_tolerance * h;
    o.direction_converged = [this, radius, limit](const Vector&, const Vector& dx) {
      for (int b = 0; b < system_.num_bodies(); ++b)
        if (dx.segment<3>(6 * b).norm() +
                dx.segment<3>(6 * b + 3).norm() * radius[static_cast<std::size_t>(b)] >
            limit)
          return false;
      return true;
    };
  }
  if (contact && step_options_.stiffness.adaptive) {
    const double d_hat = contact->potential().options().activation_distance;
    auto previous = std::make_shared<double>(contact->min_distance(q, d_hat));
    o.after_step = [this, contact, previous, d_hat](const Vector& x) {
      const double distance = contact->min_distance(x, d_hat);
      const contact::StiffnessOptions& s = step_options_.stiffness;
      const double kappa = contact->potential().options().stiffness;
      contact->potential().set_stiffness(contact::raised_stiffness(
          kappa, *previous, distance, distance_threshold(), s.growth, s.max_stiffness));
      *previous = distance;
    };
  }
  Vector y = model_.elimination().restrict_state(q);
  const NewtonResult result = newton_.solve(Vector(), y);
  if (result.converged()) q = model_.state(y, Vector());
  return result;
}

NewtonResult RigidTimeStepper::step() {
  const double h = inertia_.time_step();
  report_ = RigidStepReport{};
  RigidContactTerm* contact = step_options_.contact;
  inertia_.predict(motion_);
  if (step_options_.loads) step_options_.loads->set_reference(q_);
  Elimination& elimination = model_.elimination();
  const Vector offset = elimination.offset();
  const Vector target = system_.prescribed_state(time_ + h, q_);

  // The start: the previous state, or the explicit prediction cut back by CCD.
  Vector q = q_;
  if (step_options_.initial_guess == InitialGuess::predicted) {
    const Vector dq = elimination.expand_direction(elimination.restrict_state(predicted_state()) -
                                                   elimination.restrict_state(q_));
    if (!dq.allFinite()) {
      NewtonResult refused;
      refused.status = NewtonStatus::non_finite;
      refused.message = "the predicted initial guess is not finite (a NaN or infinite velocity)";
      return refused;
    }
    const double alpha = std::min(1.0, model_.max_step(q_, dq));
    report_.initial_step = alpha;
    q = q_ + alpha * dq;
  }
  // Adaptive stiffness: raised to the balance at the start of the solve (with the friction of the
  // previous step, in balance with the barrier there) when that is at least `growth` times kappa
  // (an impact; small changes would only disturb resting contacts). It never decreases (a lowered
  // kappa would let resting bodies sink and their lagged normal forces drift).
  if (contact && step_options_.stiffness.adaptive) {
    const contact::StiffnessOptions& s = step_options_.stiffness;
    const Vector barrier = contact->unit_stiffness_gradient(q);
    const double kappa = contact->potential().options().stiffness;
    const Vector other = model_.gradient(q, Vector()) - kappa * barrier;
    const double balanced = contact::balanced_stiffness(
        elimination.reduce(other), elimination.reduce(barrier), s.min_stiffness, s.max_stiffness);
    if (balanced >= s.growth * kappa) contact->potential().set_stiffness(balanced);
  }

  if (step_options_.friction) step_options_.friction->lag(q_, q_, h);

  // Kinematic bodies: stages towards the prescribed pose, each as far as CCD allows.
  std::vector<int> kinematic;
  for (int b = 0; b < system_.num_bodies(); ++b)
    if (system_.body(b).kinematic)
      for (int k = 0; k < 6; ++k) kinematic.push_back(6 * b + k);
  // From the second stage on, the other bodies are moved along with the kinematic ones by the
  // secant of the previous stage (their displacement per unit of kinematic motion), so that a
  // pushed body makes way in the guess and CCD lets the kinematic body go further.
  NewtonResult result;
  Vector response = Vector::Zero(q.size());
  double response_length = 0.0;
  for (int stage = 1;; ++stage) {
    Vector remaining = Vector::Zero(q.size());
    for (int dof : kinematic) remaining[dof] = target[dof] - q[dof];
    const double length = remaining.norm();
    if (length == 0.0 && stage > 1) break;
    Vector move = remaining;
    if (response_length > 0.0) move += (length / response_length) * response;
    double alpha = 1.0;
    if (!move.allFinite()) {
      elimination.set_offset(offset);
      result.status = NewtonStatus::non_finite;
      result.message = "a kinematic body's move is not finite (stage " + std::to_string(stage) + ")";
      return result;
    }
    if (length > 0.0) alpha = std::min(1.0, model_.max_step(q, move));
    if (!(alpha > 0.0)) {
      elimination.set_offset(offset);
      result.status = NewtonStatus::line_search_failed;
      result.message = "a kinematic body cannot move without touching another body (CCD step 0)";
      return result;
    }
    const Vector before = q;
    q += alpha * move;
    for (int dof : kinematic) q[dof] = alpha == 1.0 ? target[dof] : before[dof] + alpha * remaining[dof];
    Vector fixed_values = elimination.offset();
    for (int dof : kinematic) fixed_values[dof] = q[dof];
    elimination.set_offset(fixed_values);
    result = solve(q);
    report_.newton_iterations += result.iterations;
    report_.kinematic_stages = stage;
    if (!result.converged()) {
      elimination.set_offset(offset);
      return result;
    }
    if (alpha == 1.0) break;
    response = q - before;
    for (int dof : kinematic) response[dof] = 0.0;
    response_length = alpha * length;
    if (stage == step_options_.max_kinematic_stages) {
      elimination.set_offset(offset);
      result.status = NewtonStatus::max_iterations;
      result.message =
          "kinematic bodies did not reach their pose within " + std::to_string(stage) + " stages";
      return result;
    }
  }
  for (int i = 1; step_options_.friction && i < step_options_.friction_iterations; ++i) {
    step_options_.friction->lag(q, q_, h);
    result = solve(q);
    report_.newton_iterations += result.iterations;
    if (!result.converged()) {
      elimination.set_offset(offset);
      return result;
    }
  }
  q_ = q;
  time_ += h;
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
  if (contact) {
    report_.stiffness = contact->potential().options().stiffness;
    report_.min_distance = contact->min_distance(q_, contact->potential().options().activation_distance);
  }
  return result;
}

}  // namespace tailor::rigid
