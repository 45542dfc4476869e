#pragma once
// Implicit time integration as a sequence of incremental potentials (docs/methods.md section 1):
// each step minimises
//   Pi(x) = c/2 ||x - x~||^2_M - g^T x + E(x, p) + kappa D((x - x^)/kappa, p)
// with NewtonSolver over the model's free unknowns (x = x0(t) + S y), where E is the sum of
// the model's other terms (elastic, gravity, loads at t_{n+1}), the inertia term holds
// (c, x~, g) and the damping term (if any) the velocity map (kappa, x^). All three schemes
// make the new velocity v_{n+1} = (x_{n+1} - x^)/kappa.
//
//   scheme          c          x~                                         x^ / kappa              g
//   implicit_euler  1/h^2      x_n + h v_n                                x_n / h                  0
//   newmark         4/h^2      x_n + h v_n                                x_n + h v_n/2 / h/2      M a_n
//   bdf2            9/(4h^2)   (4x_n - x_{n-1})/3 + 2h(4v_n - v_{n-1})/9   (4x_n - x_{n-1})/3 / 2h/3 0
//
// newmark is the average-acceleration (trapezoidal) rule, beta = 1/4, gamma = 1/2: second
// order, unconditionally stable and without numerical dissipation on linear problems (the
// energy 1/2 v^T M v + 1/2 x^T K x is conserved exactly), and still an incremental potential
// that evaluates E at x_{n+1} only, so every energy term applies unchanged (implicit midpoint
// would need E at (x_n + x_{n+1})/2). Its memory a_n is carried as the force g = M a_n,
// updated by g_{n+1} = c M (x_{n+1} - x~) - g_n, and started from g_0 = -dE/dx(x_0) - dD/dv(v_0):
// no solve with M is ever needed. bdf2 starts with one implicit Euler step.
#include <functional>
#include <memory>

#include "forward/dynamics/damping_term.hpp"
#include "forward/dynamics/inertia_term.hpp"
#include "forward/dynamics/time_dependent.hpp"
#include "forward/solve/newton.hpp"

namespace tailor {

enum class TimeScheme { implicit_euler, newmark, bdf2 };
std::string to_string(TimeScheme scheme);
TimeScheme parse_time_scheme(const std::string& name);  // throws std::invalid_argument

// The elimination offset x0(t) (values of constrained DOFs, see Elimination) as a function of
// time: prescribed motions.
using PrescribedMotion = std::function<Vector(double time)>;

struct TimeIntegratorOptions {
  TimeScheme scheme = TimeScheme::implicit_euler;
  double time_step = 1e-2;  // h [time]
  NewtonOptions newton = [] {
    NewtonOptions o;
    o.relative_tolerance = 1e-10;
    o.max_iterations = 40;  // a step from a good predictor needs a few; stalls at round-off end sooner
    return o;
  }();
  PrescribedMotion prescribed_motion;  // empty: the elimination's offset stays
};

// Everything the next step reads; positions and velocities in full DOF space.
struct DynamicState {
  int step = 0;
  double time = 0.0;
  Vector y;  // free unknowns of x
  Vector x, v;
  Vector x_previous, v_previous;  // bdf2: the state one step before (empty at step 0)
  Vector carried_force;           // newmark: M a_n
  double residual_scale = 0.0;    // largest initial step residual so far (Newton's reference)
  double residual_floor = 0.0;    // round-off level of the step residual (Newton's absolute tolerance)
};

// One step as linear maps of the history (see the table above).
struct StepMap {
  double inertia = 0.0;         // c
  double velocity_scale = 0.0;  // kappa
  double predictor_x = 0, predictor_v = 0, predictor_x_previous = 0, predictor_v_previous = 0;
  double base_x = 0, base_v = 0, base_x_previous = 0;
  bool carries_force = false;
};

class TimeIntegrator {
 public:
  // The model must hold exactly one InertiaTerm and at most one DampingTerm; terms that are
  // TimeDependent get the time of each step. The model must outlive the integrator, and its
  // elimination must be set before (Newton's assembler is built from it here).
  TimeIntegrator(Model& model, TimeIntegratorOptions options);

  // The state at t = 0 from initial positions and velocities (full DOF space).
  DynamicState initial_state(const Vector& x0, const Vector& v0, const Vector& p);
  StepMap step_map(const DynamicState& from) const;
  // Sets the terms, the time and the prescribed offset for the step that starts at `from`.
  void configure_step(const DynamicState& from, const Vector& p);
  // Sets the terms for the evaluation of g_0 at the initial state (inertia off, D at v_0).
  void configure_initial_force(const Vector& x0, const Vector& v0);
  // Advances one step. On failure the state is left unchanged and the result says why.
  NewtonResult step(DynamicState& state, const Vector& p);

  // 1/2 v^T M v and the potential energy of every term other than inertia and damping at the
  // time last configured.
  double kinetic_energy(const Vector& v, const Vector& p) const;
  double potential_energy(const Vector& x, const Vector& p) const;

  Model& model() { return model_; }
  NewtonSolver& newton() { return newton_; }
  InertiaTerm& inertia() { return *inertia_; }
  DampingTerm* damping() { return damping_; }
  const TimeIntegratorOptions& options() const { return options_; }

 private:
  Vector history_combination(const DynamicState& s, double cx, double cv, double cxp, double cvp) const;
  Model& model_;
  TimeIntegratorOptions options_;
  InertiaTerm* inertia_ = nullptr;
  DampingTerm* damping_ = nullptr;
  std::vector<TimeDependent*> time_dependent_;
  NewtonSolver newton_;
};

}  // namespace tailor
