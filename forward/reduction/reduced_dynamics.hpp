#pragma once
// Implicit time integration in reduced coordinates q (u = Phi q), dense Newton on r unknowns
// (docs/methods.md section 7; Barbic & James 2005, section 5):
//
//   M_q q'' + C_q q' + s f(q) = f_ext,    f = dW/dq (ReducedElasticModel),
//   C_q = alpha M_q + beta s K_q(0)      (Rayleigh damping; = alpha I + beta s Lambda for
//                                         M-orthonormal linear modes, diagonal),
//
// with s a uniform material scale (s W: all Young's moduli times s) and f_ext = Phi^T f_ext
// constant. Units: time in s, alpha in 1/s, beta in s.
//
// Integrators (time step h):
//  - implicit Euler: v' = (q' - q) / h and M (v' - v) / h + C v' + s f(q') = f_ext;
//  - Newmark average acceleration (beta = 1/4, gamma = 1/2, unconditionally stable and
//    energy-conserving for linear undamped systems): a' = 4 (q' - q - h v) / h^2 - a,
//    v' = v + h (a + a') / 2 and M a' + C v' + s f(q') = f_ext; a_0 from the equation of
//    motion at t = 0.
// Each step minimises the matching incremental potential by Newton's method with a
// backtracking line search on it (dense LDL^T of the r x r Jacobian).
#include <string>
#include <vector>

#include "forward/reduction/reduced_elastic_model.hpp"

namespace tailor {

enum class ReducedIntegrator { implicit_euler, newmark };
// Newton's Jacobian: re-evaluated at every iteration (quadratic convergence), or evaluated and
// factorized once per step at the predictor and reused (chord method: linear convergence to
// the same solution, but the O(r^4) stiffness is evaluated once per step instead of once per
// iteration).
enum class ReducedJacobian { every_iteration, once_per_step };
std::string to_string(ReducedIntegrator integrator);

struct ReducedDynamicsOptions {
  ReducedIntegrator integrator = ReducedIntegrator::implicit_euler;
  double time_step = 1e-2;          // h [s], > 0
  double rayleigh_mass = 0.0;       // alpha [1/s], >= 0
  double rayleigh_stiffness = 0.0;  // beta [s], >= 0
  double material_scale = 1.0;      // s, > 0
  ReducedJacobian jacobian = ReducedJacobian::every_iteration;
  int max_newton_iterations = 30;
  // Accept the iterate after max_newton_iterations even when unconverged (no failure). With
  // max_newton_iterations = 1 this is the linearly implicit scheme of Barbic & James 2005
  // (one Newton step per time step, no line search): cheapest, approximate.
  bool accept_unconverged = false;
  // Converged when |residual| <= tolerance * (|M_q accel| + |C_q v| + |s f| + |f_ext|) (or the
  // Newton step falls below 1e-3 * tolerance * (1 + |q|), at round-off).
  double newton_tolerance = 1e-12;
};

struct ReducedState {
  Vector q, v, a;  // coordinates, velocities, accelerations (a: Newmark only)
};

struct ReducedTrajectory {
  std::vector<ReducedState> states;  // steps + 1, states[0] the initial one
  int newton_iterations = 0;         // in total
  bool converged = true;             // every step converged
  std::string message;
};

class ReducedDynamics {
 public:
  // mass: r x r symmetric positive definite (empty = identity, for M-orthonormal bases);
  // external_force: r (empty = zero). Throws std::invalid_argument on bad options or sizes.
  ReducedDynamics(const ReducedElasticModel& model, ReducedDynamicsOptions options, Matrix mass = {},
                  Vector external_force = {});

  int size() const { return model_.size(); }
  const ReducedDynamicsOptions& options() const { return options_; }
  const ReducedElasticModel& model() const { return model_; }
  const Matrix& mass() const { return mass_; }
  const Vector& external_force() const { return external_force_; }
  const Matrix& rest_stiffness() const { return rest_stiffness_; }  // K_q(0), unscaled
  Matrix damping() const;                                           // C_q

  // The initial state for (q0, v0): a0 from the equation of motion (Newmark).
  ReducedState initial_state(const Vector& q0, const Vector& v0) const;
  // One step from `current`; returns false (with a message) when Newton did not converge.
  bool step(const ReducedState& current, ReducedState& next, int& iterations, std::string& message) const;
  // `steps` steps from (q0, v0). Stops early (converged = false) when a step fails.
  ReducedTrajectory simulate(const Vector& q0, const Vector& v0, int steps) const;

  // The Newton Jacobian dR/dq' of a step ending at q' (used by the adjoint).
  Matrix step_jacobian(const Vector& q_next) const;

 private:
  const ReducedElasticModel& model_;
  ReducedDynamicsOptions options_;
  Matrix mass_, rest_stiffness_;
  Vector external_force_;
};

// Displacements of chosen vertices along a trajectory: rows (Phi rows of the vertices, k dim x
// r, from vertex_rows) times q per state; (steps + 1) x (k dim), vertex-interleaved.
Matrix vertex_rows(const Matrix& basis, const std::vector<int>& vertices, int dim);
Matrix vertex_displacements(const ReducedTrajectory& trajectory, const Matrix& rows);

// Reduced coordinates of a full-space displacement or velocity u for an M-orthonormal basis:
// q = Phi^T M u (the M-orthogonal projection onto span(Phi)).
Vector project_to_basis(const Matrix& basis, const SparseMatrix& mass, const Vector& u);

// One call for comparisons with full-space simulations: from full-space initial displacement
// u0 and velocity v0 (projected), `steps` steps, the displacements of `vertices` per state:
// (steps + 1) x (|vertices| dim), vertex-interleaved. Throws std::runtime_error with the step's
// message when a step fails.
Matrix simulate_vertex_displacements(const ReducedDynamics& dynamics, const Matrix& basis,
                                     const SparseMatrix& mass, const std::vector<int>& vertices, int dim,
                                     const Vector& u0, const Vector& v0, int steps);

}  // namespace tailor
