// The forward tangent pass of TransientFunctional (transient_functional.hpp): the states'
// directional derivatives dx_n/dz dz, in step order. Each step solved S^T R(x) = 0 with
//   R(x) = c M(p) (x - x~) - g + dE/dx(x, p) + dD/dv((x - x^)/kappa, p),
// x~ and x^ linear in the history (StepMap), so with H the step's exact Hessian (the matrix
// Newton factorizes) its tangent is, differentiating R = 0 (docs/methods.md section 2),
//   H dx = c M dx~ + H_D dx^ + dg - (d2 Pi/dx dp) dp,        H_D = d2D/dv2 / kappa,
//   dv = (dx - dx^) / kappa,   dg' = c M (dx - dx~) + (d2 Pi_inertia/dx dp) dp - dg   (Newmark),
// solved as the backward pass solves its step (solve_step_hessian). Every line is the transpose
// of one line of backward_step, so <vjp(w), dz> = <w, jvp(dz)> up to the linear tolerance.
#include <stdexcept>

#include "adjoint/transient_functional.hpp"
#include "forward/dynamics/example_damping.hpp"

namespace tailor {

// Tangents of the parts of one DynamicState (those of x_previous and v_previous for BDF2).
struct TransientFunctional::Tangent {
  Vector x, v, x_previous, v_previous, force;
};

namespace {

// (d2 E_t/dx dp) dp of one term at x; empty when the term has no parameter dependence.
Vector mixed_times(const EnergyTerm& term, const Vector& x, const Vector& p, const Vector& dp) {
  Triplets triplets;
  term.add_mixed(x, p, triplets);
  if (triplets.empty()) return {};
  SparseMatrix mixed(x.size(), p.size());
  mixed.setFromTriplets(triplets.begin(), triplets.end());
  return mixed * dp;
}

}  // namespace

void TransientFunctional::tangent_step(const DynamicState& from, const DynamicState& to, const Vector& dp,
                                       Tangent& t) {
  integrator_.configure_step(from, p_);
  const StepMap m = integrator_.step_map(from);
  const Model& model = integrator_.model();
  InertiaTerm& inertia = integrator_.inertia();
  const MassOperator& mass = inertia.mass();
  const double c = m.inertia, kappa = m.velocity_scale;

  Vector predictor = m.predictor_x * t.x + m.predictor_v * t.v;  // dx~
  if (m.predictor_x_previous != 0.0) predictor += m.predictor_x_previous * t.x_previous;
  if (m.predictor_v_previous != 0.0) predictor += m.predictor_v_previous * t.v_previous;
  Vector base = m.base_x * t.x + m.base_v * t.v;  // dx^
  if (m.base_x_previous != 0.0) base += m.base_x_previous * t.x_previous;

  Vector rhs = Vector::Zero(to.x.size());
  mass.add_times(p_, predictor, rhs, c);
  if (DampingTerm* damping = integrator_.damping()) damping->add_hessian_times(to.x, p_, base, rhs);
  if (m.carries_force) rhs += t.force;
  Vector inertia_mixed;  // Newmark: the inertia term's product also enters the carried force
  if (dp.squaredNorm() > 0.0)
    for (const auto& term : model.terms()) {
      Vector product = mixed_times(*term, to.x, p_, dp);
      if (product.size() == 0) continue;
      rhs -= product;
      if (term.get() == &inertia && m.carries_force) inertia_mixed = std::move(product);
    }
  Vector dx = solve_step_hessian(to, rhs, false);

  Tangent next;
  next.v = (dx - base) / kappa;
  next.force = Vector::Zero(dx.size());
  if (m.carries_force) {
    next.force = -t.force;
    mass.add_times(p_, dx - predictor, next.force, c);
    if (inertia_mixed.size()) next.force += inertia_mixed;
  }
  next.x_previous = std::move(t.x);
  next.v_previous = std::move(t.v);
  next.x = std::move(dx);
  t = std::move(next);
}

Matrix TransientFunctional::trajectory_jvp(const Vector& z, const Vector& dz) {
  if (dz.size() != size())
    throw std::invalid_argument("TransientFunctional::trajectory_jvp: dz has " + std::to_string(dz.size()) +
                                " entries, expected " + std::to_string(size()));
  if (dynamic_cast<const ExampleDamping*>(integrator_.damping()))
    throw std::invalid_argument(
        "TransientFunctional::trajectory_jvp: example-based damping lags its coefficients at the step's "
        "start, a dependence the tangent pass does not carry (use the vector-Jacobian product)");
  forward(z);
  const Model& model = integrator_.model();
  const Eigen::Index n = x_init_.size();
  const int N = options_.steps, np = model.parameter_layout().size();
  const Vector dP = parameterization_->jacobian_times(z, dz);
  const Vector dp = dP.head(np);
  Tangent t;
  Eigen::Index offset = np;
  t.x = options_.design_initial_positions ? Vector(dP.segment(offset, n)) : Vector::Zero(n);
  if (options_.design_initial_positions) offset += n;
  t.v = options_.design_initial_velocities ? Vector(dP.segment(offset, n)) : Vector::Zero(n);
  t.x_previous = t.v_previous = t.force = Vector::Zero(n);
  if (integrator_.options().scheme == TimeScheme::newmark) {
    // g_0 = -dPi_0/dx(x_0), Pi_0 = E + h D((x - x_0 + h v_0)/h): the transpose of the backward
    // pass's start terms.
    integrator_.configure_initial_force(x_init_, v_init_);
    if (DampingTerm* damping = integrator_.damping())
      damping->add_hessian_times(x_init_, p_, t.x - integrator_.options().time_step * t.v, t.force);
    if (options_.design_initial_positions) t.force -= model.hessian_times(x_init_, p_, t.x);
    if (dp.squaredNorm() > 0.0) t.force -= model.mixed(x_init_, p_) * dp;
  }
  have_factor_ = false;
  factor_step_ = -1;
  Matrix out(N + 1, n);
  out.row(0) = t.x.transpose();
  if (options_.checkpoint_interval <= 1) {
    for (int step = 0; step < N; ++step) {
      tangent_step(stored_[step], stored_[step + 1], dp, t);
      out.row(step + 1) = t.x.transpose();
    }
    return out;
  }
  // Checkpointed: the states are recomputed from the first one alongside the tangents.
  DynamicState from = stored_.front();
  for (int step = 0; step < N; ++step) {
    DynamicState to = from;
    const NewtonResult r = integrator_.step(to, p_);
    if (!r.converged()) throw EvaluationError("recomputation of step " + std::to_string(step + 1) + " failed");
    if (r.factorizations() > 0) newton_factor_step_ = to.step;
    tangent_step(from, to, dp, t);
    out.row(step + 1) = t.x.transpose();
    from = std::move(to);
  }
  return out;
}

}  // namespace tailor
