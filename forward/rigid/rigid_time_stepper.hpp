#pragma once
// Implicit Euler time stepping of rigid bodies (docs/methods.md section 1): each step minimizes
// the incremental potential (RigidInertiaTerm + the model's other terms: gravity, loads, IPC
// contact, lagged friction) by
// Newton, whose line search starts from the contact term's CCD step, so every accepted step is
// intersection-free; then v = (T_{n+1} - T_n) / h, Rdot = (R_{n+1} - R_n) / h. Rotation vectors
// are wrapped to |w| <= pi between steps (same rotation), away from the parameterization's
// singularity at 2 pi.
//
// Per step, with the parts given in RigidStepOptions:
//  - kinematic bodies (RigidBody::kinematic) move to their pose at t_{n+1}: in stages, each as
//    far as CCD allows with the other bodies where the last stage left them, each stage a Newton
//    solve; only the last stage (at the prescribed pose) is the step's solution, the others give
//    it an intersection-free start;
//  - the initial guess is the explicit prediction (T + h v, R continued at its angular
//    velocity) cut back by CCD from the start of the step (`predicted`), or the start itself;
//  - torque references (RigidLoadTerm::set_reference) and friction (FrictionTerm::lag) are
//    lagged at the start of the step; with friction_iterations > 1 the friction is lagged again
//    at each solution and the step solved again from there;
//  - adaptive barrier stiffness (barrier_stiffness.hpp): kappa raised to the balance at the
//    start of the step when that is larger, and after Newton iterations while the smallest
//    distance keeps shrinking below the threshold; it never decreases;
//  - IPC's stopping criterion: the step also ends when the Newton direction moves no surface
//    vertex faster than velocity_tolerance, max_v |dx_v| / h (|dx_v| <= |dT| + |dw| |V| for a rigid
//    vertex).
#include <vector>

#include "forward/contact/barrier_stiffness.hpp"
#include "forward/core/model.hpp"
#include "forward/rigid/friction_term.hpp"
#include "forward/rigid/rigid_contact_term.hpp"
#include "forward/rigid/rigid_inertia_term.hpp"
#include "forward/rigid/rigid_load_term.hpp"
#include "forward/solve/newton.hpp"

namespace tailor::rigid {

enum class InitialGuess { previous, predicted };

struct RigidStepOptions {
  RigidContactTerm* contact = nullptr;  // adaptive stiffness, CCD of guesses and kinematic stages
  FrictionTerm* friction = nullptr;     // lagged at the start of each step
  RigidLoadTerm* loads = nullptr;       // torque references moved to each step's start
  InitialGuess initial_guess = InitialGuess::previous;
  double velocity_tolerance = 0.0;  // [length / time]; 0: Newton's own tests only
  int friction_iterations = 1;      // solves per step with friction (lagged again between them)
  contact::StiffnessOptions stiffness;
  int max_kinematic_stages = 1000;
};

// What one step did besides Newton's result.
struct RigidStepReport {
  int newton_iterations = 0;  // over all stages and friction iterations
  int kinematic_stages = 0;   // solves needed to bring kinematic bodies to their pose
  double initial_step = 1.0;  // CCD fraction of the predicted guess that was kept
  double stiffness = 0.0;     // kappa at the end of the step
  double min_distance = 0.0;  // smallest distance after the step (within d_hat; infinity if none)
};

class RigidTimeStepper {
 public:
  // `model` holds `inertia` and the other terms over the system's DOFs; all must outlive the
  // stepper. Starts from the bodies' initial poses at rest.
  RigidTimeStepper(const RigidBodySystem& system, Model& model, RigidInertiaTerm& inertia,
                   NewtonOptions options = {}, RigidStepOptions step_options = {});

  // One step; on a Newton failure the state is left unchanged and the result says why.
  NewtonResult step();
  const RigidStepReport& last_report() const { return report_; }
  const Vector& state() const { return q_; }
  double time() const { return time_; }
  const std::vector<RigidMotion>& motion() const { return motion_; }
  void set_velocity(int body, const Eigen::Vector3d& velocity, const Eigen::Vector3d& angular_velocity);
  const RigidStepOptions& step_options() const { return step_options_; }
  // Newton's settings for the next steps (e.g. progress output).
  NewtonOptions& newton_options() { return options_; }

 private:
  Vector predicted_state() const;
  NewtonResult solve(Vector& q);
  double distance_threshold() const;
  const RigidBodySystem& system_;
  Model& model_;
  RigidInertiaTerm& inertia_;
  NewtonOptions options_;
  RigidStepOptions step_options_;
  NewtonSolver newton_;
  Vector q_;
  double time_ = 0.0;
  std::vector<RigidMotion> motion_;
  RigidStepReport report_;
};

}  // namespace tailor::rigid
