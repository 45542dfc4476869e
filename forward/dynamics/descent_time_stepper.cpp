#include "forward/dynamics/descent_time_stepper.hpp"

#include <algorithm>

namespace tailor {

DescentTimeStepper::DescentTimeStepper(TimeIntegrator& integrator, DescentOptions options)
    : integrator_(integrator), solver_(integrator.model(), std::move(options)) {}

DescentResult DescentTimeStepper::step(DynamicState& state, const Vector& p) {
  integrator_.configure_step(state, p);
  const StepMap m = integrator_.step_map(state);
  Model& model = integrator_.model();
  Vector y = state.y;  // warm start: the previous step's solution
  const double absolute = solver_.options().absolute_tolerance;
  solver_.options().reference_residual = state.residual_scale;
  solver_.options().absolute_tolerance = std::max(absolute, state.residual_floor);
  DescentResult result = solver_.solve(p, y);
  solver_.options().absolute_tolerance = absolute;
  if (!result.usable()) return result;
  // The state update of TimeIntegrator::step: v = (x - x^) / kappa, Newmark's carried force,
  // BDF2's history.
  const Vector x = model.state(y, p);
  DynamicState next;
  next.step = state.step + 1;
  next.time = state.time + integrator_.options().time_step;
  next.y = y;
  Vector base = m.base_x * state.x + m.base_v * state.v;
  if (m.base_x_previous != 0.0) base += m.base_x_previous * state.x_previous;
  next.v = (x - base) / m.velocity_scale;
  if (m.carries_force) {
    Vector force = Vector::Zero(x.size());
    integrator_.inertia().mass().add_times(p, x - integrator_.inertia().predictor(), force, m.inertia);
    next.carried_force = force - state.carried_force;
  }
  if (integrator_.options().scheme == TimeScheme::bdf2) {
    next.x_previous = state.x;
    next.v_previous = state.v;
  }
  next.x = x;
  next.residual_scale = std::max(state.residual_scale, result.initial_residual);
  next.residual_floor = state.residual_floor;
  state = std::move(next);
  return result;
}

}  // namespace tailor
