#pragma once
// Small rigid scenes shared by the rigid tests.
#include "forward/rigid/rigid_body_system.hpp"

namespace tailor::rigid::testing {

// A fixed box `ground_size` with its top face at z = 0, and a free box `size` whose bottom
// face is `gap` above it, centred at (offset.x, offset.y), rotated by w.
inline RigidBodySystem box_on_ground(const Eigen::Vector3d& ground_size, const Eigen::Vector3d& size,
                                     double gap, const Eigen::Vector2d& offset, const Eigen::Vector3d& w,
                                     double density = 1.0) {
  Eigen::MatrixX3d v;
  Eigen::MatrixX3i f;
  box_surface(ground_size, v, f);
  RigidBody ground = rigid_body_from_mesh("ground", v, f, density, true);
  ground.position = Eigen::Vector3d(0, 0, -0.5 * ground_size.z());
  box_surface(size, v, f);
  RigidBody box = rigid_body_from_mesh("box", v, f, density);
  box.position = Eigen::Vector3d(offset.x(), offset.y(), 0.5 * size.z() + gap);
  box.rotation = w;
  return RigidBodySystem({ground, box});
}

}  // namespace tailor::rigid::testing
