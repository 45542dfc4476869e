#include "adjoint/reduced_dynamics_functional.hpp"

#include <Eigen/Cholesky>
#include <chrono>
#include <stdexcept>

namespace tailor {

TrackedDisplacements::TrackedDisplacements(Matrix rows, std::vector<Vector> targets)
    : rows_(std::move(rows)), targets_(std::move(targets)) {
  for (const Vector& t : targets_)
    if (t.size() != rows_.rows())
      throw std::invalid_argument("TrackedDisplacements: a target has the wrong size");
}

double TrackedDisplacements::evaluate(int n, const Vector& q, Vector* gradient) const {
  if (n < 0 || n >= static_cast<int>(targets_.size()))
    throw std::invalid_argument("TrackedDisplacements: no target for state " + std::to_string(n));
  const double w = 1.0 / static_cast<double>(targets_.size());
  const Vector misfit = rows_ * q - targets_[static_cast<std::size_t>(n)];
  if (gradient) *gradient = w * (rows_.transpose() * misfit);
  return 0.5 * w * misfit.squaredNorm();
}

ReducedDynamicsFunctional::ReducedDynamicsFunctional(const ReducedElasticModel& model,
                                                     ReducedDynamicsOptions options, Matrix mass,
                                                     Vector external_force, int steps,
                                                     std::shared_ptr<const ReducedTrajectoryObjective> objective)
    : model_(model),
      options_(options),
      mass_(std::move(mass)),
      external_force_(std::move(external_force)),
      steps_(steps),
      objective_(std::move(objective)) {
  if (steps_ < 1) throw std::invalid_argument("ReducedDynamicsFunctional: steps must be >= 1");
  if (!objective_) throw std::invalid_argument("ReducedDynamicsFunctional: no objective");
  (void)dynamics(pack(Vector::Zero(model.size()), Vector::Zero(model.size()), 0.0, 0.0, 1.0));  // validates
}

Vector ReducedDynamicsFunctional::pack(const Vector& q0, const Vector& v0, double alpha, double beta,
                                       double scale) {
  Vector z(q0.size() + v0.size() + 3);
  z << q0, v0, alpha, beta, scale;
  return z;
}

ReducedDynamics ReducedDynamicsFunctional::dynamics(const Vector& z) const {
  if (z.size() != size()) throw std::invalid_argument("ReducedDynamicsFunctional: z has the wrong size");
  ReducedDynamicsOptions o = options_;
  const int r = model_.size();
  o.rayleigh_mass = z[2 * r];
  o.rayleigh_stiffness = z[2 * r + 1];
  o.material_scale = z[2 * r + 2];
  return ReducedDynamics(model_, o, mass_, external_force_);
}

double ReducedDynamicsFunctional::forward(const Vector& z) {
  const auto begin = std::chrono::steady_clock::now();
  const int r = model_.size();
  const ReducedDynamics dyn = dynamics(z);
  trajectory_ = dyn.simulate(z.head(r), z.segment(r, r), steps_);
  ++counters_.evaluations;
  ++counters_.forward_solves;
  counters_.forward_seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  if (!trajectory_.converged) throw EvaluationError("reduced dynamics: " + trajectory_.message);
  double j = 0.0;
  for (std::size_t n = 0; n < trajectory_.states.size(); ++n)
    j += objective_->evaluate(static_cast<int>(n), trajectory_.states[n].q, nullptr);
  return j;
}

double ReducedDynamicsFunctional::value(const Vector& z) { return forward(z); }

double ReducedDynamicsFunctional::value_and_gradient(const Vector& z, Vector& gradient) {
  const double j = forward(z);
  const auto begin = std::chrono::steady_clock::now();
  const int r = model_.size();
  const ReducedDynamics dyn = dynamics(z);
  const ReducedDynamicsOptions& o = dyn.options();
  const double h = o.time_step, alpha = o.rayleigh_mass, beta = o.rayleigh_stiffness, s = o.material_scale;
  const bool newmark = o.integrator == ReducedIntegrator::newmark;
  const Matrix& M = mass_.size() ? mass_ : dyn.mass();
  const Matrix& A0 = dyn.rest_stiffness();
  const Matrix C = dyn.damping();
  const auto& states = trajectory_.states;
  const int N = static_cast<int>(states.size()) - 1;

  // Adjoints of the state at n + 1 (totals), swept backwards.
  Vector q_bar = Vector::Zero(r), v_bar = Vector::Zero(r), a_bar = Vector::Zero(r), g;
  double alpha_bar = 0.0, beta_bar = 0.0, s_bar = 0.0;
  objective_->evaluate(N, states[static_cast<std::size_t>(N)].q, &g);
  q_bar += g;
  Vector f, dummy;
  Matrix K;
  for (int n = N - 1; n >= 0; --n) {
    const ReducedState& c = states[static_cast<std::size_t>(n)];
    const ReducedState& x = states[static_cast<std::size_t>(n + 1)];
    Vector q_prev_bar = Vector::Zero(r), v_prev_bar = Vector::Zero(r), a_prev_bar = Vector::Zero(r);
    Vector q_next_bar = q_bar;
    if (newmark) {
      // v' = v + h (a + a') / 2, then a' = 4 (q' - q - h v) / h^2 - a.
      v_prev_bar += v_bar;
      a_prev_bar += 0.5 * h * v_bar;
      const Vector a_next_bar = a_bar + 0.5 * h * v_bar;
      q_next_bar += 4.0 / (h * h) * a_next_bar;
      q_prev_bar -= 4.0 / (h * h) * a_next_bar;
      v_prev_bar -= 4.0 / h * a_next_bar;
      a_prev_bar -= a_next_bar;
    } else {
      // v' = (q' - q) / h.
      q_next_bar += v_bar / h;
      q_prev_bar -= v_bar / h;
    }
    // Implicit step R(q'; q, v, a, theta) = 0: lambda = J^{-T} q'_bar, then
    // input_bar -= (dR/dinput)^T lambda.
    model_.evaluate(x.q, nullptr, &f, &K);
    const Matrix J =
        (newmark ? 4.0 / (h * h) : 1.0 / (h * h)) * M + (newmark ? 2.0 / h : 1.0 / h) * C + s * K;
    const Vector lambda = J.ldlt().solve(q_next_bar);
    const Vector velocity = newmark ? x.v : Vector((x.q - c.q) / h);  // the velocity C multiplies in R
    if (newmark) {
      q_prev_bar += (4.0 / (h * h)) * (M * lambda) + (2.0 / h) * (C * lambda);
      v_prev_bar += (4.0 / h) * (M * lambda) + C * lambda;
      a_prev_bar += M * lambda;
    } else {
      q_prev_bar += (M * lambda) / (h * h) + (C * lambda) / h;
      v_prev_bar += (M * lambda) / h;
    }
    alpha_bar -= lambda.dot(M * velocity);
    beta_bar -= s * lambda.dot(A0 * velocity);
    s_bar -= lambda.dot(f + beta * (A0 * velocity));
    objective_->evaluate(n, c.q, &g);
    q_bar = q_prev_bar + g;
    v_bar = v_prev_bar;
    a_bar = a_prev_bar;
  }
  if (newmark) {
    // a_0 = M^{-1} (f_ext - C v_0 - s f(q_0)).
    const ReducedState& c = states.front();
    model_.evaluate(c.q, nullptr, &f, &K);
    const Vector mu = M.ldlt().solve(a_bar);
    v_bar -= C * mu;
    q_bar -= s * (K * mu);
    alpha_bar -= mu.dot(M * c.v);
    beta_bar -= s * mu.dot(A0 * c.v);
    s_bar -= mu.dot(f + beta * (A0 * c.v));
  }
  (void)alpha;
  gradient.resize(size());
  gradient << q_bar, v_bar, alpha_bar, beta_bar, s_bar;
  ++counters_.adjoint_solves;
  counters_.adjoint_seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  return j;
}

}  // namespace tailor
