#include "forward/reduction/rotating_subspace_dynamics.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "forward/reduction/domain_rotations.hpp"

namespace tailor {
namespace {

// The parts of P(dq) that do not depend on dq, for one step: P(dq) = 1/2 dq.A dq - b.dq +
// E(x_0 + u + B dq) - f_B.dq (up to a constant).
struct StepSystem {
  Matrix B, A;
  Vector b, f_B;
};

StepSystem step_system(const Matrix& B, const Matrix& MB, const Matrix& CB, const Vector& f, const SubspaceState& c,
                       double h) {
  StepSystem s;
  s.B = B;
  s.A = B.transpose() * ((4.0 / (h * h)) * MB + (2.0 / h) * CB);
  s.A = 0.5 * (s.A + s.A.transpose()).eval();
  s.b = MB.transpose() * (4.0 / h * c.v + c.a) + CB.transpose() * c.v;
  s.f_B = B.transpose() * f;
  return s;
}

}  // namespace

RotatingSubspaceDynamics::RotatingSubspaceDynamics(const Model& elastic, const Mesh& mesh, Vector p, Vector rest,
                                                   SparseMatrix mass, Vector external_force, Matrix basis,
                                                   Matrix weights, RotatingSubspaceOptions options)
    : elastic_(elastic),
      mesh_(mesh),
      p_(std::move(p)),
      rest_(std::move(rest)),
      mass_(std::move(mass)),
      external_force_(std::move(external_force)),
      basis_(std::move(basis)),
      weights_(std::move(weights)),
      options_(options) {
  const Eigen::Index n = elastic.num_dofs();
  if (mesh.dim() != 3 || n != 3 * mesh.num_vertices())
    throw std::invalid_argument("RotatingSubspaceDynamics: a 3D mesh whose vertices are the model's DOFs is needed");
  if (rest_.size() != n || mass_.rows() != n || mass_.cols() != n || basis_.rows() != n ||
      weights_.rows() != mesh.num_vertices())
    throw std::invalid_argument("RotatingSubspaceDynamics: the rest state, mass, basis and weights need " +
                                std::to_string(n) + " DOFs / " + std::to_string(mesh.num_vertices()) + " vertices");
  if (external_force_.size() == 0) external_force_ = Vector::Zero(n);
  if (external_force_.size() != n) throw std::invalid_argument("RotatingSubspaceDynamics: the load has the wrong size");
  if (basis_.cols() < 1 || weights_.cols() < 1)
    throw std::invalid_argument("RotatingSubspaceDynamics: the basis and the weights need a column");
  if (!(options_.time_step > 0.0) || options_.rayleigh_mass < 0.0 || options_.rayleigh_stiffness < 0.0 ||
      options_.max_newton_iterations < 1 || !(options_.newton_tolerance > 0.0))
    throw std::invalid_argument("RotatingSubspaceDynamics: time_step > 0, Rayleigh coefficients >= 0, "
                                "max_newton_iterations >= 1 and newton_tolerance > 0 are needed");
  vertex_mass_ = vertex_masses(mass_);
  if (options_.rayleigh_stiffness > 0.0)
    for (const auto& term : elastic_.terms()) rest_hessians_.push_back(term->hessian(rest_, p_, HessianMode::exact));
}

// Products with the sum of the terms' Hessians, term by term (no sparse sum is formed).
Matrix RotatingSubspaceDynamics::stiffness_times(const Vector& x, HessianMode mode, const Matrix& B) const {
  Matrix kb = Matrix::Zero(B.rows(), B.cols());
  for (const auto& term : elastic_.terms()) kb += term->hessian(x, p_, mode) * B;
  return kb;
}

Matrix RotatingSubspaceDynamics::damping_times(const Matrix& B) const {
  Matrix cb = options_.rayleigh_mass * (mass_ * B);
  for (const SparseMatrix& k : rest_hessians_) cb += options_.rayleigh_stiffness * (k * B);
  return cb;
}

Matrix RotatingSubspaceDynamics::step_basis(const Vector& u) const {
  if (!options_.rotations) return basis_;
  return rotate_basis(basis_, weights_, fit_domain_rotations(mesh_, u, vertex_mass_, weights_), options_.blend);
}

SubspaceState RotatingSubspaceDynamics::initial_state(const Vector& v0) const {
  if (v0.size() != rest_.size()) throw std::invalid_argument("RotatingSubspaceDynamics: v0 has the wrong size");
  const Matrix MB = mass_ * basis_;
  const Eigen::LDLT<Matrix> mq((basis_.transpose() * MB).eval());
  SubspaceState s;
  s.u = Vector::Zero(rest_.size());
  s.v = basis_ * mq.solve(MB.transpose() * v0);
  s.a = basis_ * mq.solve(basis_.transpose() * (external_force_ - damping_times(Matrix(s.v))));
  return s;
}

void RotatingSubspaceDynamics::step_potential(const SubspaceState& c, const Matrix& B, const Vector& dq,
                                              double* value, Vector* gradient, Matrix* hessian) const {
  const StepSystem s = step_system(B, mass_ * B, damping_times(B), external_force_, c, options_.time_step);
  const Vector x = rest_ + c.u + B * dq;
  if (value) *value = 0.5 * dq.dot(s.A * dq) - s.b.dot(dq) + elastic_.energy(x, p_) - s.f_B.dot(dq);
  if (gradient) *gradient = s.A * dq - s.b + B.transpose() * elastic_.gradient(x, p_) - s.f_B;
  if (hessian) {
    *hessian = s.A + B.transpose() * stiffness_times(x, HessianMode::exact, B);
    *hessian = 0.5 * (*hessian + hessian->transpose()).eval();
  }
}

bool RotatingSubspaceDynamics::step(const SubspaceState& current, SubspaceState& next, int& iterations,
                                    std::string& message) const {
  const double h = options_.time_step;
  const Matrix B = step_basis(current.u);
  SubspaceState c = current;
  const Matrix MB = mass_ * B;
  const Eigen::LDLT<Matrix> mq((B.transpose() * MB).eval());
  if (mq.info() != Eigen::Success || !mq.isPositive()) {
    message = "the turned basis is singular";
    return false;
  }
  if (options_.rotations) {  // v and a onto span(B), M-orthogonally
    c.v = B * mq.solve(MB.transpose() * current.v);
    c.a = B * mq.solve(MB.transpose() * current.a);
  }
  const StepSystem s = step_system(B, MB, damping_times(B), external_force_, c, h);
  const auto potential = [&](const Vector& dq, double elastic) {
    return 0.5 * dq.dot(s.A * dq) - s.b.dot(dq) + elastic - s.f_B.dot(dq);
  };
  // Predictor: the constant-acceleration displacement h v + h^2 a / 4, projected.
  Vector dq = mq.solve(MB.transpose() * (h * c.v + 0.25 * h * h * c.a));
  Vector x = rest_ + c.u + B * dq;
  double energy = elastic_.energy(x, p_);
  iterations = 0;
  for (int it = 0;; ++it) {
    const Vector elastic_force = B.transpose() * elastic_.gradient(x, p_);
    const Vector inertia = s.A * dq - s.b;
    const Vector residual = inertia + elastic_force - s.f_B;
    const double scale = inertia.norm() + elastic_force.norm() + s.f_B.norm() + s.b.norm();
    if (!residual.allFinite()) {
      message = "the step's residual is not finite";
      return false;
    }
    if (residual.norm() <= options_.newton_tolerance * scale || residual.norm() == 0.0) break;
    if (it == options_.max_newton_iterations) {
      message = "Newton did not converge in " + std::to_string(options_.max_newton_iterations) +
                " iterations (residual " + std::to_string(residual.norm()) + ")";
      return false;
    }
    // The exact Jacobian; where it is not positive definite (StVK under compression), the
    // element Hessians projected to PSD instead (a descent direction for the line search; the
    // minimizer is the same, only the path to it changes), as the full-space Newton does.
    Matrix jacobian = s.A + B.transpose() * stiffness_times(x, HessianMode::exact, B);
    jacobian = 0.5 * (jacobian + jacobian.transpose()).eval();
    Eigen::LDLT<Matrix> ldlt(jacobian);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) {
      jacobian = s.A + B.transpose() * stiffness_times(x, HessianMode::projected, B);
      ldlt.compute(0.5 * (jacobian + jacobian.transpose()));
    }
    const Vector step = -ldlt.solve(residual);
    if (!step.allFinite()) {
      message = "the Newton system is singular";
      return false;
    }
    // Backtracking on P when the step is a descent direction (as ReducedDynamics).
    const double e0 = potential(dq, energy), slope = step.dot(residual);
    double t = 1.0;
    Vector trial = dq + step;
    x = rest_ + c.u + B * trial;
    energy = elastic_.energy(x, p_);
    if (ldlt.isPositive() && slope < 0.0) {
      for (int k = 0; k < 30 && !(potential(trial, energy) <= e0 + 1e-4 * t * slope); ++k) {
        t *= 0.5;
        trial = dq + t * step;
        x = rest_ + c.u + B * trial;
        energy = elastic_.energy(x, p_);
      }
    }
    dq = trial;
    ++iterations;
    if (t * step.norm() <= 1e-3 * options_.newton_tolerance * (1.0 + dq.norm())) break;
  }
  const Vector d = B * dq;
  next.u = c.u + d;
  next.a = 4.0 / (h * h) * (d - h * c.v) - c.a;
  next.v = c.v + 0.5 * h * (c.a + next.a);
  if (!next.u.allFinite() || !next.v.allFinite()) {
    message = "the state is not finite";
    return false;
  }
  return true;
}

double RotatingSubspaceDynamics::total_energy(const SubspaceState& state) const {
  return 0.5 * state.v.dot(mass_ * state.v) + elastic_.energy(rest_ + state.u, p_) - external_force_.dot(state.u);
}

double RotatingSubspaceDynamics::smallest_volume_ratio(const Vector& u) const {
  double smallest = std::numeric_limits<double>::infinity();
  for (int e = 0; e < mesh_.num_elements(); ++e) {
    Eigen::Matrix3d rest_edges, edges;
    for (int k = 0; k < 3; ++k) {
      const int a = mesh_.elements(e, 0), b = mesh_.elements(e, k + 1);
      rest_edges.col(k) = (mesh_.rest_positions.row(b) - mesh_.rest_positions.row(a)).transpose();
      edges.col(k) = rest_edges.col(k) + u.segment<3>(3 * b) - u.segment<3>(3 * a);
    }
    smallest = std::min(smallest, edges.determinant() / rest_edges.determinant());
  }
  return smallest;
}

}  // namespace tailor
