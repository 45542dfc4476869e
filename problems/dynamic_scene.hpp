#pragma once
// Dynamic scenes: the optional "dynamics" section of a scene turns `tailor simulate` into a
// time integration (forward/dynamics) of the scene's static model plus inertia and Rayleigh
// damping. Loads (gravity included) act from t = 0 as dead loads, prescribed displacements are
// applied from t = 0, and the body starts at rest positions with the given initial velocity.
// Output: DIR/frames/frame_NNNN.vtu every `output_every` steps, DIR/result.pvd (a ParaView
// time series) and DIR/report.json with per-step energies, Newton iterations and timings.
// With an "objective" in the section, `tailor gradcheck` Taylor-tests its gradient.
#include <iosfwd>
#include <optional>
#include <string>

#include "forward/dynamics/time_integrator.hpp"
#include "forward/fem/mass.hpp"
#include "objectives/trajectory_objective.hpp"
#include "problems/inverse_report.hpp"
#include "problems/scene.hpp"

namespace tailor {

// The trajectory objective of `tailor gradcheck` on a dynamic scene: the selected vertices'
// positions (rest position + `target`) or velocities (`target`) at the listed steps.
struct TrajectoryTargetSpec {
  VertexSelector vertices;
  TrajectoryQuantity quantity = TrajectoryQuantity::position;
  std::vector<int> steps;  // empty: the last step
  Eigen::VectorXd target;
  std::string key = "dynamics.objective";
};

struct DynamicsSpec {
  TimeScheme scheme = TimeScheme::implicit_euler;
  double time_step = 0.01;  // h [time]
  int steps = 100;
  MassLumping lumping = MassLumping::consistent;
  double rayleigh_alpha = 0.0;                      // [1/time]
  double rayleigh_beta = 0.0;                       // [time]; K is the rest stiffness
  int output_every = 1;                             // write a frame every this many steps (and the last)
  std::optional<Eigen::VectorXd> initial_velocity;  // uniform, one entry per dimension
  std::optional<TrajectoryTargetSpec> objective;    // for `tailor gradcheck`
};

struct DynamicRun {
  bool completed = false;  // every step converged
  std::string message;
  int steps_done = 0;
  std::string report_path, series_path;
};

// Throws SceneError for scene problems (e.g. a material without a positive density).
DynamicRun simulate_dynamic_scene(const Scene& scene, const std::string& out_dir, std::ostream* log);

// Taylor test of the time-dependent adjoint (TransientFunctional) of the scene's trajectory
// objective over all its steps, in per-element log Young's modulus, per-element log density and,
// with Rayleigh damping, alpha and beta; writes out_dir/gradcheck.json. Throws SceneError when
// the dynamics section has no objective.
GradcheckRun gradcheck_dynamic_scene(const Scene& scene, const std::string& out_dir, unsigned seed,
                                     std::ostream* log);

}  // namespace tailor
