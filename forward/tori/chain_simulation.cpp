// Chains of tori in implicit Euler steps, implicit or mesh contact (see chain_simulation.hpp).
#include "forward/tori/chain_simulation.hpp"

#include <chrono>
#include <functional>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "forward/contact/barrier_stiffness.hpp"
#include "forward/core/elimination.hpp"
#include "forward/rigid/rigid_gravity_term.hpp"
#include "forward/tori/mesh_intersections.hpp"

namespace tailor::tori {
namespace {

// A contact term with its max_step (CCD) timed, the rest passed through: both contact models'
// CCD share is measured the same way.
class CcdTimedTerm final : public EnergyTerm {
 public:
  CcdTimedTerm(std::unique_ptr<EnergyTerm> inner, double& seconds) : inner_(std::move(inner)), seconds_(seconds) {}
  std::string name() const override { return inner_->name(); }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override {
    inner_->evaluate(x, p, request);
  }
  void hessian_pattern(HessianPattern& pattern) const override { inner_->hessian_pattern(pattern); }
  void add_param_gradient(const Vector& x, const Vector& p, Vector& g) const override {
    inner_->add_param_gradient(x, p, g);
  }
  void add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const override { inner_->add_mixed(x, p, mixed); }
  double max_step(const Vector& x, const Vector& dx) const override {
    const auto start = std::chrono::steady_clock::now();
    const double alpha = inner_->max_step(x, dx);
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return alpha;
  }

 private:
  std::unique_ptr<EnergyTerm> inner_;
  double& seconds_;
};

}  // namespace

ChainSimulation::ChainSimulation(const ChainSpec& chain_spec, const ChainSimulationOptions& options)
    : options_(options) {
  if (!(options.time_step > 0.0)) throw std::invalid_argument("ChainSimulation: time_step must be positive");
  ChainSpec spec = chain_spec;
  spec.inscribed = options.model == ContactModel::implicit;  // mesh IPC: vertices on the surface
  Chain chain = make_chain(spec);
  shapes_ = chain.shapes;
  system_ = std::make_unique<rigid::RigidBodySystem>(chain.bodies);
  d_hat_ = options.activation_distance > 0.0 ? options.activation_distance : 1e-2 * spec.shape.minor_radius;
  double weight = 0.0, link_mass = 0.0;
  for (const rigid::RigidBody& body : system_->bodies())
    if (!body.fixed) {
      weight += body.mass * options.gravity.norm();
      link_mass = std::max(link_mass, body.mass);
    }
  const double force = std::max(weight, link_mass * d_hat_ / (options.time_step * options.time_step));
  kappa_ = options.stiffness > 0.0 ? options.stiffness : contact::stiffness_for_force(force, d_hat_);
  contact::StiffnessOptions& control = options_.stiffness_control;
  if (control.adaptive) {
    if (!(control.min_stiffness >= 0.0) || !(control.max_stiffness >= 0.0))
      throw std::invalid_argument("ChainSimulation: min_stiffness and max_stiffness must be >= 0 (0: default)");
    if (control.min_stiffness > 0.0) kappa_ = control.min_stiffness;
    control.min_stiffness = kappa_;
    if (!(control.max_stiffness > 0.0)) control.max_stiffness = 100.0 * kappa_;  // IPC's ratio
    if (!(control.max_stiffness >= control.min_stiffness))
      throw std::invalid_argument("ChainSimulation: max_stiffness " + std::to_string(control.max_stiffness) +
                                  " is below min_stiffness " + std::to_string(control.min_stiffness));
    if (!(control.growth > 1.0) || !std::isfinite(control.growth))
      throw std::invalid_argument("ChainSimulation: the stiffness growth factor must exceed 1");
    if (!(control.distance_fraction > 0.0 && control.distance_fraction < 1.0))
      throw std::invalid_argument("ChainSimulation: the stiffness distance_fraction must lie in (0, 1)");
  }
  const bool friction = options.friction.coefficient != 0.0;

  model_ = std::make_unique<Model>(system_->num_dofs());
  inertia_ = &model_->add(std::make_unique<rigid::RigidInertiaTerm>(*system_, options.time_step));
  model_->add(std::make_unique<rigid::RigidGravityTerm>(*system_, options.gravity));
  rigid::RigidStepOptions step_options;
  const double length = spec.count * spec.effective_spacing() + 2.0 * spec.shape.major_radius;
  step_options.velocity_tolerance =
      (options.direction_tolerance > 0.0 ? options.direction_tolerance : 1e-10 * length) / options.time_step;
  if (options.model == ContactModel::implicit) {
    TorusContactOptions o;
    o.activation_distance = d_hat_;
    o.stiffness = kappa_;
    o.pair_band = options.pair_band;
    auto term = std::make_unique<TorusContactTerm>(*system_, shapes_, o);
    implicit_ = term.get();
    model_->add(std::make_unique<CcdTimedTerm>(std::move(term), ccd_seconds_));
    if (friction) {
      TorusFrictionOptions f;
      f.friction = options.friction;
      implicit_friction_ = &model_->add(std::make_unique<TorusFrictionTerm>(*system_, *implicit_, f));
    }
  } else {
    contact::ContactOptions o;
    o.activation_distance = d_hat_;
    o.stiffness = kappa_;
    auto term = std::make_unique<rigid::RigidContactTerm>(*system_, o);
    mesh_ = term.get();
    model_->add(std::make_unique<CcdTimedTerm>(std::move(term), ccd_seconds_));
    step_options.contact = mesh_;
    step_options.stiffness = control;
    if (friction) {
      mesh_friction_ = &model_->add(std::make_unique<rigid::FrictionTerm>(*mesh_, options.friction));
      step_options.friction = mesh_friction_;
    }
  }
  model_->set_elimination(Elimination::dirichlet(system_->fixed_dofs(), system_->initial_state()));
  // The start: the implicit tori apart (every pair, cheap), and the meshes of the mesh model too
  // (their chords can reach past the implicit surface).
  {
    TorusContactOptions o;
    const TorusContactTerm exact(*system_, shapes_, o);
    if (!(exact.min_distance(system_->initial_state(), Vector(), 1e300) > 0.0))
      throw std::invalid_argument("ChainSimulation: the tori intersect at the start");
    if (mesh_ && count_body_intersections(*system_, system_->initial_state()) > 0)
      throw std::invalid_argument("ChainSimulation: the tori's meshes intersect at the start (more segments?)");
  }
  NewtonOptions newton = options.newton;
  if (!(newton.absolute_tolerance > 0.0))
    newton.absolute_tolerance = options.residual_tolerance > 0.0 ? options.residual_tolerance : 1e-6 * weight;
  stepper_ = std::make_unique<rigid::RigidTimeStepper>(*system_, *model_, *inertia_, newton, step_options);
  if (implicit_ && control.adaptive) {
    // IPC's update after each Newton iteration (the stepper's own is for the mesh barrier).
    std::function<void(const Vector&)> inner = newton.after_step;
    stepper_->newton_options().after_step = [this, inner](const Vector& x) {
      if (inner) inner(x);
      const contact::StiffnessOptions& c = options_.stiffness_control;
      const double distance = implicit_->min_distance(x, Vector(), d_hat_);
      implicit_->set_stiffness(contact::raised_stiffness(implicit_->options().stiffness, previous_distance_,
                                                         distance, c.distance_fraction * d_hat_, c.growth,
                                                         c.max_stiffness));
      previous_distance_ = distance;
    };
  }
}

double ChainSimulation::stiffness() const {
  if (implicit_) return implicit_->options().stiffness;
  return mesh_->potential().options().stiffness;
}

void ChainSimulation::raise_stiffness_to_balance() {
  // The balance of Li et al. 2020 (section 4.3) at the start of the step, with the inertia term
  // at this step's prediction (the stepper predicts again from the same motion).
  const Vector& q = stepper_->state();
  inertia_->predict(stepper_->motion());
  const double kappa = implicit_->options().stiffness;
  Vector barrier = Vector::Zero(q.size());
  EnergyRequest request;
  request.gradient = &barrier;
  implicit_->evaluate(q, Vector(), request);
  barrier /= kappa;  // the barrier's gradient at kappa = 1
  const Vector other = model_->gradient(q, Vector()) - kappa * barrier;
  const contact::StiffnessOptions& c = options_.stiffness_control;
  const Elimination& elimination = model_->elimination();
  const double balanced = contact::balanced_stiffness(elimination.reduce(other), elimination.reduce(barrier),
                                                      c.min_stiffness, c.max_stiffness);
  if (balanced >= c.growth * kappa) implicit_->set_stiffness(balanced);
  previous_distance_ = implicit_->min_distance(q, Vector(), d_hat_);
}

double ChainSimulation::min_distance(double range) const {
  const Vector& q = stepper_ ? stepper_->state() : system_->initial_state();
  if (implicit_) {
    // Every pair: the implicit distance is cheap.
    const double r = std::isfinite(range) ? range : 1e300;
    return implicit_->min_distance(q, Vector(), r);
  }
  return mesh_->min_distance(q, std::min(range, 10.0 * d_hat_));
}

int ChainSimulation::active_pairs() const {
  const Vector& q = stepper_->state();
  if (implicit_) return implicit_->active_pairs(q, Vector());
  int count = 0;
  mesh_->potential().for_each_active(mesh_->bodies().positions(q), false,
                                     [&](const contact::ActivePair&) { ++count; });
  return count;
}

ChainStepRecord ChainSimulation::step() {
  ChainStepRecord record;
  const double ccd_before = ccd_seconds_;
  const auto start = std::chrono::steady_clock::now();
  if (implicit_ && options_.stiffness_control.adaptive) raise_stiffness_to_balance();
  // Friction lagged at the start of the step, with kappa as just raised (the mesh model's
  // stepper lags its own term).
  if (implicit_friction_) implicit_friction_->lag(stepper_->state(), stepper_->state(), options_.time_step);
  result_ = stepper_->step();
  const NewtonResult& result = result_;
  record.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  record.converged = result.converged();
  record.newton_iterations = stepper_->last_report().newton_iterations;
  record.ccd_seconds = ccd_seconds_ - ccd_before;
  record.min_distance = min_distance(d_hat_);
  record.active_pairs = active_pairs();
  record.intersections = options_.check_intersections ? count_body_intersections(*system_, stepper_->state()) : -1;
  record.stiffness = stiffness();
  std::pair<int, int> slip{0, 0};
  if (implicit_friction_) slip = implicit_friction_->sliding_and_sticking(stepper_->state());
  if (mesh_friction_) slip = mesh_friction_->sliding_and_sticking(stepper_->state());
  record.sliding = slip.first;
  record.sticking = slip.second;
  return record;
}

bool ChainSimulation::relax(double tolerance, int max_steps, std::vector<ChainStepRecord>* records) {
  if (implicit_friction_ || mesh_friction_)
    throw std::invalid_argument(
        "ChainSimulation::relax: friction is for dynamics (implicit Euler steps of the real time step); a "
        "static relaxation is frictionless");
  for (int n = 0; n < max_steps; ++n) {
    const Vector before = stepper_->state();
    const ChainStepRecord record = step();
    if (records) records->push_back(record);
    if (!record.converged) return false;
    if ((stepper_->state() - before).lpNorm<Eigen::Infinity>() <= tolerance) return true;
  }
  return false;
}

}  // namespace tailor::tori
