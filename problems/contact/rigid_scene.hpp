#pragma once
// Contact scenes (`rigid_bodies`, `fem_bodies`, `contact` sections) for `tailor simulate` and
// `tailor gradcheck`: rigid bodies (forward/rigid) and FEM bodies with IPC contact
// (forward/contact) in static equilibrium, or rigid bodies in implicit Euler steps with lagged
// friction and kinematic bodies. Keys are documented in docs/contact.md. JSON is parsed here
// into typed structs (rigid_scene_parse.cpp); the numerical code never sees it.
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "adjoint/taylor_test.hpp"
#include "forward/contact/barrier_stiffness.hpp"
#include "forward/contact/contact_potential.hpp"
#include "forward/contact/friction.hpp"
#include "forward/rigid/rigid_body_system.hpp"
#include "forward/rigid/rigid_time_stepper.hpp"
#include "forward/solve/newton.hpp"

namespace tailor {

struct Scene;     // problems/fem/scene.hpp
class SceneNode;  // problems/scene_node.hpp

// An FEM body of a contact scene: the FEM scene's keys (mesh, materials, dirichlet, loads) as a
// parsed Scene. Its boundary triangles take part in contact; it does not touch itself.
struct FemBodySpec {
  std::string name;
  std::shared_ptr<const Scene> scene;
};

struct RigidSceneSpec {
  std::string name, description, source;
  std::vector<rigid::RigidBody> bodies;
  std::vector<std::vector<int>> fixed_body_dofs;  // per body: local DOFs 0..5 held fixed
  std::vector<Eigen::Vector3d> forces, torques;   // per body: constant force [N] and torque [N m] (world)
  std::vector<FemBodySpec> fem_bodies;
  Eigen::Vector3d gravity = Eigen::Vector3d(0, 0, -9.81);
  contact::ContactOptions contact;
  contact::StiffnessOptions stiffness;  // adaptive kappa (contact.stiffness = "adaptive")
  contact::FrictionOptions friction;    // dynamic scenes only
  int friction_iterations = 1;
  NewtonOptions newton;
  // Dynamics (implicit Euler) when time_step > 0; initial velocities per body.
  double time_step = 0.0;  // [time]
  int steps = 0;
  int output_every = 1;  // write .vtu frames every this many steps
  std::vector<Eigen::Vector3d> velocities, angular_velocities;
  // IPC's stop on the Newton direction [length / time]; 0: off; < 0: 1e-8 x the scene's bounding
  // box diagonal per unit time (a guard against residuals stalling at round-off).
  double velocity_tolerance = -1.0;
  rigid::InitialGuess initial_guess = rigid::InitialGuess::previous;
  bool has_torques() const;
};

// The scene's document; `directory` resolves the paths of mesh files. Throws SceneError naming
// the source and the key path of a bad value (unknown keys included).
RigidSceneSpec parse_rigid_scene(const SceneNode& root, const std::string& directory);

struct RigidSimulateRun {
  NewtonResult newton;
  Vector state;           // (T_b, w_b) per body, then the FEM bodies' vertex positions
  Vector contact_forces;  // -dB/dq per DOF (force on each body, generalized moment on w, FEM nodal forces)
  std::vector<Eigen::Vector3d> contact_moments;     // per rigid body: sum (x - T) x f over its vertices [N m]
  std::vector<Eigen::Vector3d> fem_contact_forces;  // per FEM body: total contact force [N]
  std::vector<Eigen::Vector3d> velocities, angular_velocities;  // dynamic: per rigid body at the end
  double min_distance = 0;  // smallest distance between bodies (over all steps when dynamic)
  int active_pairs = 0;
  int steps_completed = 0;    // dynamic: accepted steps
  int intersections = 0;      // edge-face crossings found after the solve or any step (must be 0)
  int newton_iterations = 0;  // over all solves (re-lags, kinematic stages, friction iterations)
  double stiffness = 0;       // kappa at the end
  bool completed() const { return newton.converged() && intersections == 0; }
};

// Solves the static equilibrium (re-solving with the torques' reference moved to the solution
// until it stays, when there are torques), or with a time step runs the implicit Euler steps
// (checking distances and edge-face crossings after each); writes DIR/report.json and
// DIR/<body>.vtu (static) or DIR/<body>_<frame>.vtu (dynamic). Progress to `log` when given.
RigidSimulateRun simulate_rigid_scene(const RigidSceneSpec& spec, const std::string& out_dir,
                                      std::ostream* log);

// `tailor gradcheck` on a rigid scene: a Taylor test of the static adjoint gradient of
//   J(m) = 1/2 sum_b |T_b(m) - T_b^0|^2   (free bodies' centres against their initial places)
// with respect to the body masses m (gravity's parameters), through the contact equilibrium.
// Writes DIR/gradcheck.json. Throws SceneError when no body is free, for dynamic scenes and for
// scenes with FEM bodies, torques or adaptive stiffness.
TaylorTestResult gradcheck_rigid_scene(const RigidSceneSpec& spec, const std::string& out_dir, unsigned seed,
                                       std::ostream* log);

}  // namespace tailor
