#include "forward/reduction/reduced_dynamics.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <stdexcept>

namespace tailor {

std::string to_string(ReducedIntegrator integrator) {
  return integrator == ReducedIntegrator::implicit_euler ? "implicit_euler" : "newmark";
}

ReducedDynamics::ReducedDynamics(const ReducedElasticModel& model, ReducedDynamicsOptions options,
                                 Matrix mass, Vector external_force)
    : model_(model), options_(options), mass_(std::move(mass)), external_force_(std::move(external_force)) {
  const int r = model.size();
  if (!(options_.time_step > 0.0)) throw std::invalid_argument("ReducedDynamics: time_step must be > 0");
  if (!(options_.rayleigh_mass >= 0.0) || !(options_.rayleigh_stiffness >= 0.0))
    throw std::invalid_argument("ReducedDynamics: Rayleigh coefficients must be >= 0");
  if (!(options_.material_scale > 0.0))
    throw std::invalid_argument("ReducedDynamics: material_scale must be > 0");
  if (options_.max_newton_iterations < 1)
    throw std::invalid_argument("ReducedDynamics: max_newton_iterations must be >= 1");
  if (mass_.size() == 0) mass_ = Matrix::Identity(r, r);
  if (external_force_.size() == 0) external_force_ = Vector::Zero(r);
  if (mass_.rows() != r || mass_.cols() != r || external_force_.size() != r)
    throw std::invalid_argument("ReducedDynamics: mass must be r x r and the external force of size r = " +
                                std::to_string(r));
  rest_stiffness_ = model.stiffness(Vector::Zero(r));
}

Matrix ReducedDynamics::damping() const {
  return options_.rayleigh_mass * mass_ +
         options_.rayleigh_stiffness * options_.material_scale * rest_stiffness_;
}

ReducedState ReducedDynamics::initial_state(const Vector& q0, const Vector& v0) const {
  if (q0.size() != size() || v0.size() != size())
    throw std::invalid_argument("ReducedDynamics: initial conditions must have size r = " +
                                std::to_string(size()));
  ReducedState s{q0, v0, Vector::Zero(size())};
  if (options_.integrator == ReducedIntegrator::newmark)
    s.a = mass_.ldlt().solve(external_force_ - damping() * v0 - options_.material_scale * model_.force(q0));
  return s;
}

Matrix ReducedDynamics::step_jacobian(const Vector& q_next) const {
  const double h = options_.time_step;
  const bool newmark = options_.integrator == ReducedIntegrator::newmark;
  return (newmark ? 4.0 / (h * h) : 1.0 / (h * h)) * mass_ + (newmark ? 2.0 / h : 1.0 / h) * damping() +
         options_.material_scale * model_.stiffness(q_next);
}

bool ReducedDynamics::step(const ReducedState& c, ReducedState& next, int& iterations,
                           std::string& message) const {
  const double h = options_.time_step, s = options_.material_scale;
  const bool newmark = options_.integrator == ReducedIntegrator::newmark;
  const Matrix C = damping();
  const Matrix inertia_matrix =
      (newmark ? 4.0 / (h * h) : 1.0 / (h * h)) * mass_ + (newmark ? 2.0 / h : 1.0 / h) * C;
  // The potential whose q-gradient is the step residual, from a given W(q):
  //   implicit Euler: |q - q_n - h v|_M^2 / (2 h^2) + |q - q_n|_C^2 / (2 h) + s W(q) - f_ext.q
  //   Newmark: 2 |q - q_n - h v|_M^2 / h^2 - a.M q + |q - q_n|_C^2 / h - v.C q + s W(q) - f_ext.q
  const auto potential = [&](const Vector& q, double elastic) {
    const Vector jump = q - c.q - h * c.v, dq = q - c.q;
    const double e = s * elastic - external_force_.dot(q);
    if (!newmark) return e + jump.dot(mass_ * jump) / (2 * h * h) + dq.dot(C * dq) / (2 * h);
    return e + 2.0 * jump.dot(mass_ * jump) / (h * h) - c.a.dot(mass_ * q) + dq.dot(C * dq) / h -
           c.v.dot(C * q);
  };
  // Predictor: constant acceleration over the step (the last step's for implicit Euler).
  Vector q = c.q + h * c.v + ((newmark ? 0.25 : 1.0) * h * h) * c.a;
  iterations = 0;
  Vector force;
  Matrix stiffness;
  double energy = 0.0;
  const bool chord = options_.jacobian == ReducedJacobian::once_per_step;
  model_.evaluate(q, &energy, &force, &stiffness);
  Eigen::LDLT<Matrix> ldlt;
  for (int it = 0;; ++it) {
    // Residual: inertia + damping + elastic - external.
    const Vector jump = q - c.q - h * c.v;
    const Vector inertia =
        newmark ? Vector(mass_ * (4.0 / (h * h) * jump - c.a)) : Vector(mass_ * jump / (h * h));
    const Vector velocity = newmark ? Vector(2.0 / h * (q - c.q) - c.v) : Vector((q - c.q) / h);
    const Vector damping_force = C * velocity;
    const Vector residual = inertia + damping_force + s * force - external_force_;
    const double scale = inertia.norm() + damping_force.norm() + s * force.norm() + external_force_.norm();
    if (residual.norm() <= options_.newton_tolerance * scale || residual.norm() == 0.0) break;
    if (it == options_.max_newton_iterations) {
      message = "reduced step: Newton did not converge in " + std::to_string(options_.max_newton_iterations) +
                " iterations (residual " + std::to_string(residual.norm()) + ")";
      return false;
    }
    if (!chord || it == 0) ldlt.compute(inertia_matrix + s * stiffness);
    const Vector dq = -ldlt.solve(residual);
    if (!dq.allFinite()) {
      message = "reduced step: the Newton system is singular";
      return false;
    }
    if (options_.accept_unconverged && it + 1 == options_.max_newton_iterations) {
      q += dq;
      ++iterations;
      break;
    }
    // Backtracking on the incremental potential when the full step does not decrease it (a
    // descent direction when the Jacobian is positive definite; the full step is kept
    // otherwise). The full step is nearly always accepted, so an iteration costs one
    // evaluation of the reduced model.
    const double e0 = potential(q, energy), slope = dq.dot(residual);
    double t = 1.0;
    Vector trial = q + dq;
    const bool want_stiffness = !chord;
    model_.evaluate(trial, &energy, &force, want_stiffness ? &stiffness : nullptr);
    if (ldlt.isPositive() && slope < 0.0) {
      for (int k = 0; k < 30 && potential(trial, energy) > e0 + 1e-4 * t * slope; ++k) {
        t *= 0.5;
        trial = q + t * dq;
        energy = model_.energy(trial);
      }
      if (t < 1.0) model_.evaluate(trial, &energy, &force, want_stiffness ? &stiffness : nullptr);
    }
    q = trial;
    ++iterations;
    if (t * dq.norm() <= 1e-3 * options_.newton_tolerance * (1.0 + q.norm())) break;
  }
  next.q = q;
  if (newmark) {
    next.a = 4.0 / (h * h) * (q - c.q - h * c.v) - c.a;
    next.v = c.v + 0.5 * h * (c.a + next.a);
  } else {
    next.v = (q - c.q) / h;
    next.a = (next.v - c.v) / h;
  }
  return true;
}

ReducedTrajectory ReducedDynamics::simulate(const Vector& q0, const Vector& v0, int steps) const {
  if (steps < 0) throw std::invalid_argument("ReducedDynamics::simulate: steps must be >= 0");
  ReducedTrajectory out;
  out.states.reserve(static_cast<std::size_t>(steps) + 1);
  out.states.push_back(initial_state(q0, v0));
  for (int n = 0; n < steps; ++n) {
    ReducedState next;
    int iterations = 0;
    std::string message;
    const bool ok = step(out.states.back(), next, iterations, message);
    out.newton_iterations += iterations;
    if (!ok) {
      out.converged = false;
      out.message = "step " + std::to_string(n) + ": " + message;
      break;
    }
    out.states.push_back(std::move(next));
  }
  if (out.converged)
    out.message =
        std::to_string(steps) + " steps, " + std::to_string(out.newton_iterations) + " Newton iterations";
  return out;
}

Matrix vertex_rows(const Matrix& basis, const std::vector<int>& vertices, int dim) {
  Matrix rows(static_cast<Eigen::Index>(vertices.size()) * dim, basis.cols());
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    const int v = vertices[k];
    if (v < 0 || dim * (v + 1) > basis.rows())
      throw std::invalid_argument("vertex_rows: vertex " + std::to_string(v) + " out of range");
    rows.middleRows(static_cast<Eigen::Index>(k) * dim, dim) = basis.middleRows(dim * v, dim);
  }
  return rows;
}

Matrix vertex_displacements(const ReducedTrajectory& trajectory, const Matrix& rows) {
  Matrix out(static_cast<Eigen::Index>(trajectory.states.size()), rows.rows());
  for (std::size_t n = 0; n < trajectory.states.size(); ++n)
    out.row(static_cast<Eigen::Index>(n)) = (rows * trajectory.states[n].q).transpose();
  return out;
}

Vector project_to_basis(const Matrix& basis, const SparseMatrix& mass, const Vector& u) {
  if (mass.rows() != basis.rows() || u.size() != basis.rows())
    throw std::invalid_argument("project_to_basis: the basis, mass matrix and vector sizes differ");
  return basis.transpose() * (mass * u);
}

Matrix simulate_vertex_displacements(const ReducedDynamics& dynamics, const Matrix& basis,
                                     const SparseMatrix& mass, const std::vector<int>& vertices, int dim,
                                     const Vector& u0, const Vector& v0, int steps) {
  if (basis.cols() != dynamics.size())
    throw std::invalid_argument("simulate_vertex_displacements: the basis has " +
                                std::to_string(basis.cols()) + " columns, the reduced model " +
                                std::to_string(dynamics.size()));
  const ReducedTrajectory trajectory =
      dynamics.simulate(project_to_basis(basis, mass, u0), project_to_basis(basis, mass, v0), steps);
  if (!trajectory.converged) throw std::runtime_error("simulate_vertex_displacements: " + trajectory.message);
  return vertex_displacements(trajectory, vertex_rows(basis, vertices, dim));
}

}  // namespace tailor
