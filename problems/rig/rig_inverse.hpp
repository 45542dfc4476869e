#pragma once
// Inverse use of the rigged arm (docs/pose_space.md, "Inverse use"): the gradient of a marker's
// trajectory objective with respect to the arm's Young's moduli, per region, under the scene's
// rig motion, by the transient adjoint (adjoint/transient_functional.hpp) on the full-space
// dynamics on the moving rest shape (forward/rig/moving_rest_model.hpp, implicit Euler).
//
//   z = log E_r, r = upper arm, belly, forearm (E_e = exp(z_r(e)); the other parameters fixed),
//   J(z) = 1/2 sum_{n=1..N} |x_m(t_n) - y_n|^2 / sum_{n=1..N} |y_n - X_m(p(t_n))|^2,
//
// x_m = X_m(p(t_n)) + u_m(n) the marker vertex's world position and y_n the "measured" motion:
// the same marker simulated with the moduli scaled by `target_scale` (a synthetic measurement
// whose minimizer is known), J relative to the measured jiggle. X_m does not depend on z, so J
// is a keyframe target on u.
#include <iosfwd>
#include <memory>
#include <string>

#include "adjoint/taylor_test.hpp"
#include "adjoint/transient_functional.hpp"
#include "forward/rig/moving_rest_model.hpp"
#include "problems/rig/rig_scene.hpp"

namespace tailor {

// The arm's material regions: 0 upper arm, 1 belly (two_bone_arm's region 1), 2 forearm
// (element centroid beyond the elbow, x > length / 2).
constexpr int kArmRegions = 3;
std::vector<int> arm_material_regions(const Mesh& mesh, const TwoBoneArmOptions& arm);

struct RigMarkerInverse {
  TwoBoneArm arm;
  std::unique_ptr<Rig> rig;
  std::unique_ptr<PoseTrajectory> trajectory;
  MovingRestModel model;
  std::unique_ptr<TimeIntegrator> integrator;
  std::unique_ptr<TransientFunctional> functional;
  std::vector<int> regions;  // per element
  int marker = 0;            // vertex
  int steps = 0;
  Vector z0;                 // log of the scene's moduli per region
  Matrix target;             // steps x 3: y_n - X_m(p(t_n)), the measured marker's displacement from the rig
};

// Builds the functional for a full-space scene (throws SceneError for a reduced one: the
// reduced stepping has no adjoint) over `steps` steps (0: the scene's duration).
std::unique_ptr<RigMarkerInverse> rig_marker_inverse(const RigSceneSpec& spec, int steps,
                                                     const Eigen::Vector3d& target_scale);

// `tailor gradcheck` of a rig_dynamics scene: the Taylor test of J above at z0 (seeded
// direction); writes DIR/gradcheck.json (taylor_json plus the scene and the problem's sizes).
TaylorTestResult gradcheck_rig_scene(const RigSceneSpec& spec, const std::string& out_dir, unsigned seed,
                                     std::ostream* log);

struct RigInverseRun {
  OptimizerResult result;
  Vector expected;            // log of the target moduli per region
  double moduli_error = 0.0;  // largest |E_r / E_r^target - 1| at the result
};

// `tailor run` of a rig_dynamics scene with an "inverse" section: minimizes J from the scene's
// moduli with the section's optimizer; writes DIR/report.json (the recovered and expected
// log E per region, the optimizer's history).
RigInverseRun run_rig_inverse(const RigSceneSpec& spec, const std::string& out_dir, std::ostream* log);

}  // namespace tailor
