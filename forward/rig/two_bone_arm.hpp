#pragma once
// A generated two-bone "arm" for examples, tests and the bench: a box of tets along x,
// [0, length] x [-half_width, half_width]^2, with an upper-arm bone (root, joint at the origin,
// one rotation about z: the shoulder) and a forearm bone (joint at the elbow (length/2,
// -half_width, 0) on the bottom edge, one rotation about z: negative angles fold the forearm's
// bottom face onto the upper arm's). Skinning weights blend the two bones with a smoothstep over
// |x - length/2| < blend. The top face y = +half_width is the region fixed to the rig (the
// "bone" side); the upper arm's bottom half is a soft belly (Young's modulus times
// belly_softness). Parameters p = (shoulder, elbow) [rad].
#include "forward/rig/rigged_body.hpp"

namespace tailor {

struct TwoBoneArmOptions {
  double length = 4.0, half_width = 0.25;
  int cells_along = 16, cells_across = 3;
  double blend = 0.3;                 // half width of the skinning blend around the elbow
  double youngs_modulus = 2e5, poisson_ratio = 0.4, density = 1000.0;
  double belly_softness = 0.2;        // belly modulus / youngs_modulus
  MaterialKind material = MaterialKind::stvk;
};

struct TwoBoneArm {
  RiggedBody body;
  std::vector<Bone> bones;
  Matrix weights;  // vertices x 2
};

TwoBoneArm two_bone_arm(const TwoBoneArmOptions& options = {});
// The arm's skinning weights of a vertex at x (upper, forearm), for rig files.
Eigen::Vector2d two_bone_arm_weights(double x, const TwoBoneArmOptions& options);

}  // namespace tailor
