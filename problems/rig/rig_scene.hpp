#pragma once
// Scenes with a "rig_dynamics" section (docs/pose_space.md): a generated two-bone arm driven by a
// rig file (bones, parents, joints, degrees of freedom, per-vertex skinning weights, optional
// pose corrections) along keyframes, simulated on its moving rest shape in full space or with
// pose-space reduction. `tailor simulate` writes DIR/frames/frame_NNNNN.vtu (point fields
// rig_displacement = X(p) - Xbar and dynamic_displacement = u, drawn at X(p) + u), DIR/result.pvd,
// DIR/jiggle.png (|u| of the marker vertex and the largest |u| against time) and DIR/report.json.
#include <iosfwd>
#include <string>
#include <vector>

#include "forward/rig/pose_space_dynamics.hpp"
#include "forward/rig/two_bone_arm.hpp"
#include "optimizers/optimizer.hpp"

namespace tailor {

class SceneNode;  // problems/scene_node.hpp

struct RigReductionSpec {
  PoseSpaceOptions options;
  std::vector<Vector> example_poses;
  double contact_distance = 0.0;  // > 0: contacts at the example poses become constraints
};

// The optional "inverse" section (problems/rig/rig_inverse.hpp): the measured marker motion is
// the scene's at Young's moduli scaled by target_scale (upper arm, belly, forearm), over `steps`
// steps (0: the duration); `tailor run` recovers log E per region from it.
struct RigInverseSection {
  Eigen::Vector3d target_scale = Eigen::Vector3d(1.3, 0.7, 1.2);
  int steps = 0;
  OptimizerOptions optimizer;
};

struct RigSceneSpec {
  std::string name;
  TwoBoneArmOptions arm;
  std::vector<Bone> bones;
  Matrix weights;                       // vertices x bones
  std::vector<PoseCorrection> corrections;
  std::vector<double> key_times;
  std::vector<Vector> key_poses;
  MovingRestOptions dynamics;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  double duration = 1.0;
  int output_every = 5;
  Eigen::Vector3d marker = Eigen::Vector3d::Zero();  // the jiggle plot's point (nearest vertex)
  bool reduced = false;
  RigReductionSpec reduction;
  RigInverseSection inverse;  // defaults when the scene has none (gradcheck uses them)
  bool has_inverse = false;
};

// The scene's document; `directory` resolves a rig given as a file name. Throws SceneError naming
// the source and key path for bad input (unknown keys, weights of the wrong size, ...).
RigSceneSpec parse_rig_scene(const SceneNode& root, const std::string& directory);

struct RigSceneRun {
  bool completed = false;
  std::string message;
  int steps = 0;
  double seconds = 0.0, max_jiggle = 0.0;
};

// Runs the scene and writes its outputs into out_dir; progress on `log` when set.
RigSceneRun run_rig_scene(const RigSceneSpec& spec, const std::string& out_dir, std::ostream* log);

}  // namespace tailor
