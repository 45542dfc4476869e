#pragma once
// Rigid-body contact scenes (`rigid_bodies`, `contact` sections) for `tailor simulate`: static
// equilibrium of rigid bodies under gravity with IPC contact (forward/rigid, forward/contact).
// Keys are documented in docs/contact.md. JSON is parsed here into typed structs; the
// numerical code never sees it.
#include <iosfwd>
#include <string>
#include <vector>

#include "adjoint/taylor_test.hpp"
#include "forward/contact/contact_potential.hpp"
#include "forward/rigid/rigid_body_system.hpp"
#include "forward/solve/newton.hpp"

namespace tailor {

struct RigidSceneSpec {
  std::string name, description, source;
  std::vector<rigid::RigidBody> bodies;
  std::vector<std::vector<int>> fixed_body_dofs;  // per body: local DOFs 0..5 held fixed
  Eigen::Vector3d gravity = Eigen::Vector3d(0, 0, -9.81);
  contact::ContactOptions contact;
  NewtonOptions newton;
  // Dynamics (implicit Euler) when time_step > 0; initial velocities per body.
  double time_step = 0.0;  // [time]
  int steps = 0;
  int output_every = 1;  // write .vtu frames every this many steps
  std::vector<Eigen::Vector3d> velocities, angular_velocities;
};

// True when the file is a JSON object with a "rigid_bodies" member.
bool is_rigid_scene(const std::string& path);
// Throws SceneError naming the file and the JSON path of a bad value.
RigidSceneSpec parse_rigid_scene(const std::string& json_text, const std::string& source);
RigidSceneSpec read_rigid_scene(const std::string& path);

struct RigidSimulateRun {
  NewtonResult newton;
  Vector state;             // (T_b, w_b) per body at the equilibrium
  Vector contact_forces;    // -dB/dq per DOF (force on each body, generalized moment on w)
  double min_distance = 0;  // smallest distance between bodies (over all steps when dynamic)
  int active_pairs = 0;
  int steps_completed = 0;  // dynamic: accepted steps
  int intersections = 0;    // dynamic: edge-face crossings found after any step (must be 0)
  bool completed() const { return newton.converged() && intersections == 0; }
};

// Solves the static equilibrium, or with a time step runs the implicit Euler steps (checking
// distances and edge-face crossings after each); writes DIR/report.json and DIR/<body>.vtu
// (static) or DIR/<body>_<frame>.vtu (dynamic). Progress to `log` when given.
RigidSimulateRun simulate_rigid_scene(const RigidSceneSpec& spec, const std::string& out_dir,
                                      std::ostream* log);

// `tailor gradcheck` on a rigid scene: a Taylor test of the static adjoint gradient of
//   J(m) = 1/2 sum_b |T_b(m) - T_b^0|^2   (free bodies' centres against their initial places)
// with respect to the body masses m (gravity's parameters), through the contact equilibrium.
// Writes DIR/gradcheck.json. Throws SceneError when no body is free.
TaylorTestResult gradcheck_rigid_scene(const RigidSceneSpec& spec, const std::string& out_dir, unsigned seed,
                                       std::ostream* log);

}  // namespace tailor
