#include "forward/dynamics/time_integrator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace tailor {

std::string to_string(TimeScheme scheme) {
  switch (scheme) {
    case TimeScheme::implicit_euler:
      return "implicit_euler";
    case TimeScheme::newmark:
      return "newmark";
    case TimeScheme::bdf2:
      return "bdf2";
  }
  return "unknown";
}

TimeScheme parse_time_scheme(const std::string& name) {
  if (name == "implicit_euler") return TimeScheme::implicit_euler;
  if (name == "newmark") return TimeScheme::newmark;
  if (name == "bdf2") return TimeScheme::bdf2;
  throw std::invalid_argument("unknown time scheme '" + name +
                              "' (expected implicit_euler, newmark or bdf2)");
}

TimeIntegrator::TimeIntegrator(Model& model, TimeIntegratorOptions options)
    : model_(model), options_(std::move(options)), newton_(model, options_.newton) {
  if (!(options_.time_step > 0.0)) throw std::invalid_argument("TimeIntegrator: the time step must be > 0");
  if (newton_.assembles_by_parts())
    throw std::invalid_argument("TimeIntegrator: the linear solver '" + options_.newton.linear_solver->name() +
                                "' assembles by parts (distributed assembly), which this version does for static "
                                "scenes only: run a dynamic scene without -tailor_assemble_by_parts");
  for (const auto& term : model.terms()) {
    if (auto* inertia = dynamic_cast<InertiaTerm*>(term.get())) {
      if (inertia_) throw std::invalid_argument("TimeIntegrator: the model has more than one inertia term");
      inertia_ = inertia;
    }
    if (auto* damping = dynamic_cast<DampingTerm*>(term.get())) {
      if (damping_) throw std::invalid_argument("TimeIntegrator: the model has more than one damping term");
      damping_ = damping;
    }
    if (auto* timed = dynamic_cast<TimeDependent*>(term.get())) time_dependent_.push_back(timed);
  }
  if (!inertia_) throw std::invalid_argument("TimeIntegrator: the model has no inertia term");
}

StepMap TimeIntegrator::step_map(const DynamicState& from) const {
  const double h = options_.time_step;
  StepMap m;
  TimeScheme scheme = options_.scheme;
  if (scheme == TimeScheme::bdf2 && from.step == 0) scheme = TimeScheme::implicit_euler;  // BDF2 start-up
  switch (scheme) {
    case TimeScheme::implicit_euler:
      m.inertia = 1.0 / (h * h);
      m.velocity_scale = h;
      m.predictor_x = 1.0, m.predictor_v = h;
      m.base_x = 1.0;
      break;
    case TimeScheme::newmark:
      m.inertia = 4.0 / (h * h);
      m.velocity_scale = h / 2;
      m.predictor_x = 1.0, m.predictor_v = h;
      m.base_x = 1.0, m.base_v = h / 2;
      m.carries_force = true;
      break;
    case TimeScheme::bdf2:
      m.inertia = 9.0 / (4.0 * h * h);
      m.velocity_scale = 2.0 * h / 3.0;
      m.predictor_x = 4.0 / 3.0, m.predictor_x_previous = -1.0 / 3.0;
      m.predictor_v = 8.0 * h / 9.0, m.predictor_v_previous = -2.0 * h / 9.0;
      m.base_x = 4.0 / 3.0, m.base_x_previous = -1.0 / 3.0;
      break;
  }
  return m;
}

Vector TimeIntegrator::history_combination(const DynamicState& s, double cx, double cv, double cxp,
                                           double cvp) const {
  Vector r = cx * s.x + cv * s.v;
  if (cxp != 0.0) r += cxp * s.x_previous;
  if (cvp != 0.0) r += cvp * s.v_previous;
  return r;
}

void TimeIntegrator::configure_step(const DynamicState& from, const Vector& p) {
  (void)p;
  const StepMap m = step_map(from);
  const double t_next = from.time + options_.time_step;
  inertia_->set_step(
      m.inertia,
      history_combination(from, m.predictor_x, m.predictor_v, m.predictor_x_previous, m.predictor_v_previous),
      m.carries_force ? from.carried_force : Vector());
  if (damping_) {
    damping_->set_step_start(from.x, from.v);
    damping_->set_velocity_map(m.velocity_scale,
                               history_combination(from, m.base_x, m.base_v, m.base_x_previous, 0.0));
  }
  for (TimeDependent* term : time_dependent_) term->set_time(t_next);
  if (options_.prescribed_motion) {
    Vector offset = options_.prescribed_motion(t_next);
    if (offset.size() != model_.num_dofs())
      throw std::invalid_argument("TimeIntegrator: the prescribed motion returned " +
                                  std::to_string(offset.size()) + " values, the model has " +
                                  std::to_string(model_.num_dofs()) + " DOFs");
    model_.elimination().set_offset(offset);
  }
}

void TimeIntegrator::configure_initial_force(const Vector& x0, const Vector& v0) {
  inertia_->set_step(0.0, x0);
  const double h = options_.time_step;
  if (damping_) {
    damping_->set_step_start(x0, v0);
    damping_->set_velocity_map(h, x0 - h * v0);  // v(x0) = v0
  }
  for (TimeDependent* term : time_dependent_) term->set_time(0.0);
}

DynamicState TimeIntegrator::initial_state(const Vector& x0, const Vector& v0, const Vector& p) {
  const int n = model_.num_dofs();
  if (x0.size() != n || v0.size() != n)
    throw std::invalid_argument("TimeIntegrator: initial positions and velocities must have " +
                                std::to_string(n) + " entries");
  if (options_.prescribed_motion) {
    Vector offset = options_.prescribed_motion(0.0);
    if (offset.size() != n)
      throw std::invalid_argument("TimeIntegrator: the prescribed motion has the wrong size");
    model_.elimination().set_offset(offset);
  }
  DynamicState s;
  s.x = x0;
  s.v = v0;
  s.y = model_.elimination().restrict_state(x0);
  if (options_.scheme == TimeScheme::newmark) {
    configure_initial_force(x0, v0);
    s.carried_force = -model_.gradient(x0, p);
  }
  // Round-off level of the reduced step residual: 1e3 eps |H|_max (1 + |x|_inf) sqrt(m), H the
  // first step's Hessian. Small vibrations have initial residuals so small that a relative
  // tolerance alone would ask for more digits than the gradient has.
  configure_step(s, p);
  SparseMatrix H = newton_.assembler().hessian_pattern_matrix();
  newton_.assembler().evaluate(s.y, p, nullptr, nullptr, &H, HessianMode::exact);
  const double h_max = H.nonZeros() ? H.coeffs().cwiseAbs().maxCoeff() : 0.0;
  s.residual_floor = 1e3 * std::numeric_limits<double>::epsilon() * h_max *
                     (1.0 + x0.lpNorm<Eigen::Infinity>()) * std::sqrt(static_cast<double>(s.y.size()));
  return s;
}

NewtonResult TimeIntegrator::step(DynamicState& state, const Vector& p) {
  configure_step(state, p);
  const StepMap m = step_map(state);
  Vector y = state.y;
  // Convergence relative to the largest out-of-balance force met so far: a body coming to
  // rest has a vanishing initial residual that would make a purely relative test unreachable.
  // Newton's first iteration evaluates ||g0|| at y anyway and takes max(||g0||, reference) as
  // its scale: passing the scale so far gives the same test without a gradient evaluation here.
  double scale = state.residual_scale;
  newton_.options().reference_residual = scale;
  newton_.options().absolute_tolerance = std::max(options_.newton.absolute_tolerance, state.residual_floor);
  // Newton in chunks of a few iterations. Near rest the total potential is a sum of pieces
  // that cancel (e.g. the linear-in-strain parts of an elastic energy), so its round-off can
  // exceed the decrease of a last Newton step and the line search stalls although the
  // residual is tiny. Such a stall is accepted at the level Newton itself accepts for
  // round-off-limited steps, sqrt(relative_tolerance) * scale, after one chunk instead of
  // spending the whole iteration budget on it.
  constexpr int kChunk = 8;
  const int budget = options_.newton.max_iterations;
  NewtonResult result;
  for (int used = 0;;) {
    newton_.options().max_iterations = std::min(kChunk, budget - used);
    NewtonResult chunk = newton_.solve(p, y);
    if (used == 0) {
      scale = std::max(scale, chunk.initial_residual);  // ||g0||, at the step's start
      newton_.options().reference_residual = scale;
    }
    used += chunk.iterations;
    if (result.history.empty()) {
      result = chunk;
    } else {
      result.history.insert(result.history.end(), chunk.history.begin(), chunk.history.end());
      result.status = chunk.status, result.message = chunk.message;
      result.final_residual = chunk.final_residual, result.final_energy = chunk.final_energy;
      result.total_seconds += chunk.total_seconds;
    }
    result.iterations = used;
    if (chunk.converged() || used >= budget) break;
    const bool stalled =
        chunk.status == NewtonStatus::max_iterations || chunk.status == NewtonStatus::line_search_failed;
    if (!stalled) break;
    if (chunk.final_residual <= std::sqrt(options_.newton.relative_tolerance) * scale) {
      result.status = NewtonStatus::converged;
      result.message += "; accepted: residual at the energy's round-off level";
      break;
    }
    if (chunk.status == NewtonStatus::line_search_failed) break;
  }
  newton_.options().max_iterations = budget;
  if (!result.converged()) return result;
  const Vector x = model_.state(y, p);
  DynamicState next;
  next.step = state.step + 1;
  next.time = state.time + options_.time_step;
  next.y = y;
  const Vector base = history_combination(state, m.base_x, m.base_v, m.base_x_previous, 0.0);
  next.v = (x - base) / m.velocity_scale;
  if (m.carries_force) {
    Vector force = Vector::Zero(x.size());
    inertia_->mass().add_times(p, x - inertia_->predictor(), force, m.inertia);
    next.carried_force = force - state.carried_force;
  }
  if (options_.scheme == TimeScheme::bdf2) {
    next.x_previous = state.x;
    next.v_previous = state.v;
  }
  next.x = x;
  next.residual_scale = scale;
  next.residual_floor = state.residual_floor;
  state = std::move(next);
  return result;
}

double TimeIntegrator::kinetic_energy(const Vector& v, const Vector& p) const {
  Vector Mv = Vector::Zero(v.size());
  inertia_->mass().add_times(p, v, Mv);
  return 0.5 * v.dot(Mv);
}

double TimeIntegrator::potential_energy(const Vector& x, const Vector& p) const {
  double e = 0.0;
  for (const auto& term : model_.terms())
    if (term.get() != inertia_ && term.get() != damping_) e += term->value(x, p);
  return e;
}

}  // namespace tailor
