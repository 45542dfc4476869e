#pragma once
// A hanging chain of tori under gravity (chain.hpp) in implicit Euler steps of the rigid stepper
// (forward/rigid/rigid_time_stepper.hpp), with either contact model:
//  implicit: TorusContactTerm on the exact torus distance; the bodies' meshes are the inscribed
//            triangulations, used only for output and the intersection check;
//  mesh:     the same bodies as triangle meshes (vertices on the torus surface) with the mesh
//            IPC of RigidContactTerm (point-triangle and edge-edge barriers, additive CCD).
// Same masses, inertias (closed form), d_hat and kappa in both; kappa fixed during the run unless
// stiffness_control.adaptive.
//
// Friction (friction.coefficient > 0, dynamics only): IPC's smoothed friction, lagged once at the
// start of every step (one lagging iteration): implicit, TorusFrictionTerm between the tori's
// closest points; mesh, rigid::FrictionTerm between the mesh primitives (the stepper lags it).
// relax() refuses it (a relaxation's long steps are no dynamics to dissipate).
//
// Adaptive stiffness (stiffness_control.adaptive; barrier_stiffness.hpp, Li et al. 2020, section
// 4.3): kappa starts at min_stiffness (0: the kappa of `stiffness` below), is raised at the
// start of each step to the balance -(g_E . g_B) / |g_B|^2 of the barrier gradient against
// every other force (inertia at the step's prediction, gravity, the previous step's friction)
// when that is at least `growth` times kappa, and after each Newton iteration multiplied by
// `growth` while the smallest pair distance is below distance_fraction d_hat and still
// shrinking; at most max_stiffness (0: 100 min_stiffness), never lowered. The mesh model hands
// the same options to the rigid stepper, which does the same on the mesh barrier.
//
// Static equilibrium: steps of a long time step (static_time_step) until no DOF moves more
// than static_tolerance in a step: a fixed point of implicit Euler is at rest, so its inertia
// term vanishes and the state is in equilibrium; the inertia regularizes the chain's zero
// modes (a link turning about the vertical through its contact point) that make the static
// Hessian singular.
#include <memory>
#include <string>
#include <vector>

#include "forward/core/model.hpp"
#include "forward/contact/barrier_stiffness.hpp"
#include "forward/contact/friction.hpp"
#include "forward/rigid/friction_term.hpp"
#include "forward/rigid/rigid_contact_term.hpp"
#include "forward/rigid/rigid_inertia_term.hpp"
#include "forward/rigid/rigid_time_stepper.hpp"
#include "forward/tori/chain.hpp"
#include "forward/tori/torus_contact_term.hpp"
#include "forward/tori/torus_friction_term.hpp"

namespace tailor::tori {

enum class ContactModel { implicit, mesh };

struct ChainSimulationOptions {
  ContactModel model = ContactModel::implicit;
  Eigen::Vector3d gravity = Eigen::Vector3d(0, 0, -9.81);
  double time_step = 1e-2;        // dynamics [time]
  double activation_distance = 0.0;  // d_hat; 0: 1e-2 r
  double stiffness = 0.0;            // kappa; 0: one pair at d_hat / 2 carries the free links' weight
  int pair_band = 0;                 // implicit: candidate pairs (TorusContactTerm)
  bool check_intersections = true;   // the mesh check after every accepted step
  // IPC's stop on the Newton direction (RigidStepOptions::velocity_tolerance = this / h): no
  // point moves more than this in the step [length]; 0: 1e-10 x the chain's length. The
  // residual's relative tolerance alone is out of reach: the energy of a stiff barrier cannot
  // resolve the last Newton steps in double precision (its round-off floor).
  double direction_tolerance = 0.0;
  // Newton's absolute residual floor [force]; 0: 1e-6 x the free links' weight (the mesh model's
  // energy, summed over many pairs, stalls above the relative tolerance).
  double residual_tolerance = 0.0;
  contact::FrictionOptions friction;          // mu (0: frictionless) and eps_v, see above
  contact::StiffnessOptions stiffness_control;  // adaptive kappa, see above
  NewtonOptions newton;
};

struct ChainStepRecord {
  bool converged = false;
  int newton_iterations = 0;
  double seconds = 0.0;      // wall time of the step
  double ccd_seconds = 0.0;  // of it in CCD (max_step of the contact term)
  double min_distance = 0.0; // after the step, over pairs within d_hat (infinity if none)
  int active_pairs = 0;      // pairs (implicit) or primitive pairs (mesh) within d_hat
  int intersections = 0;     // mesh edge-face crossings after the step (-1: not checked)
  double stiffness = 0.0;    // kappa at the end of the step
  int sliding = 0, sticking = 0;  // lagged friction pairs with slip >= eps_v h, and below
};

class ChainSimulation {
 public:
  ChainSimulation(const ChainSpec& chain, const ChainSimulationOptions& options);

  // One implicit Euler step of options.time_step; on a failed solve the state stays and the
  // record says converged = false (last_message() why).
  ChainStepRecord step();
  // Static equilibrium: steps until one moves no DOF by more than `tolerance` (at most
  // max_steps; construct with a long time_step, e.g. 1 s). True when it came to rest.
  bool relax(double tolerance, int max_steps, std::vector<ChainStepRecord>* records = nullptr);

  const rigid::RigidBodySystem& system() const { return *system_; }
  const Vector& state() const { return stepper_->state(); }
  // kappa now (with adaptive stiffness: as raised so far; it never decreases).
  double stiffness() const;
  // kappa at the start (adaptive: min_stiffness).
  double initial_stiffness() const { return kappa_; }
  double activation_distance() const { return d_hat_; }
  const TorusContactTerm* implicit_term() const { return implicit_; }
  const rigid::RigidContactTerm* mesh_term() const { return mesh_; }
  const TorusFrictionTerm* implicit_friction() const { return implicit_friction_; }
  const rigid::FrictionTerm* mesh_friction() const { return mesh_friction_; }
  const std::vector<TorusShape>& shapes() const { return shapes_; }
  // Smallest distance over pairs within `range` (infinity if none): implicit, every pair in
  // range; mesh, primitive pairs within min(range, 10 d_hat) (all-pairs mesh distances are
  // quadratic in the mesh size).
  double min_distance(double range) const;
  int active_pairs() const;
  std::string last_message() const { return result_.message; }
  const NewtonResult& last_result() const { return result_; }

 private:
  ChainSimulationOptions options_;
  std::vector<TorusShape> shapes_;
  std::unique_ptr<rigid::RigidBodySystem> system_;
  std::unique_ptr<Model> model_;
  rigid::RigidInertiaTerm* inertia_ = nullptr;
  TorusContactTerm* implicit_ = nullptr;
  rigid::RigidContactTerm* mesh_ = nullptr;
  TorusFrictionTerm* implicit_friction_ = nullptr;
  rigid::FrictionTerm* mesh_friction_ = nullptr;
  void raise_stiffness_to_balance();  // implicit, adaptive: the start-of-step balance
  double previous_distance_ = 0.0;    // implicit, adaptive: the last iteration's smallest distance
  std::unique_ptr<rigid::RigidTimeStepper> stepper_;
  double d_hat_ = 0.0, kappa_ = 0.0, ccd_seconds_ = 0.0;
  NewtonResult result_;
};

}  // namespace tailor::tori
