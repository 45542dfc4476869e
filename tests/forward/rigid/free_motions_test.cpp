// Free common rigid motions (forward/rigid/free_motions.hpp). Reference: by hand, the motions of
// the whole assembly that no held DOF feels (a fixed body holds all of them; a held DOF stops
// the motions that move it).
#include "forward/rigid/free_motions.hpp"

#include <gtest/gtest.h>

#include "rigid_scenes.hpp"

namespace tailor::rigid::free_motions_test {
namespace {

// The held DOFs of body b: its local DOFs `local` (0-2 T, 3-5 w).
std::vector<int> held_of(int b, std::initializer_list<int> local) {
  std::vector<int> held;
  for (int k : local) held.push_back(6 * b + k);
  return held;
}

std::vector<FreeMotion> free_of(const RigidBodySystem& system, const Vector& q, const std::vector<int>& held,
                                const Eigen::Vector3d& centre) {
  return free_motions(rigid_system_motions(system, q, system.num_dofs(), {}, centre), held, 2.0);
}

TEST(FreeMotions, AFixedBodyHoldsEveryCommonMotion) {
  const RigidBodySystem system = testing::box_on_ground(Eigen::Vector3d(4, 4, 1), Eigen::Vector3d(1, 1, 1), 1e-3,
                                                        Eigen::Vector2d(0.1, 0.2), Eigen::Vector3d(0.1, 0.2, 0.3));
  const Vector q = system.initial_state();
  EXPECT_TRUE(free_of(system, q, system.fixed_dofs(), Eigen::Vector3d::Zero()).empty());
  // Without the ground's DOFs held, all six are free: 3 translations, then 3 rotations.
  const std::vector<FreeMotion> all = free_of(system, q, {}, Eigen::Vector3d::Zero());
  ASSERT_EQ(all.size(), 6u);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(all[static_cast<std::size_t>(k)].rotation.norm(), 0.0);
  for (int k = 3; k < 6; ++k) EXPECT_GT(all[static_cast<std::size_t>(k)].rotation.norm(), 0.5);
}

// The shipped sphere-on-box scene without its ground: the box holds x, y, rz, the sphere x, y
// and all rotations; the only motion of both together that none of these feel is the vertical
// translation. The box is turned (w != 0), so its rotation vector moves by J(w)^-1 a, not a.
TEST(FreeMotions, SphereOnBoxWithoutGroundIsFreeVertically) {
  const RigidBodySystem full = testing::box_on_ground(Eigen::Vector3d(4, 4, 1), Eigen::Vector3d(1, 1, 1), 5e-3,
                                                      Eigen::Vector2d(0, 0), Eigen::Vector3d(0.2, -0.1, 0.3));
  std::vector<RigidBody> bodies = {full.body(1), full.body(1)};
  bodies[1].name = "sphere";
  bodies[1].position += Eigen::Vector3d(0.1, 0.3, 1.0);
  bodies[1].rotation.setZero();
  const RigidBodySystem system(bodies);
  std::vector<int> held = held_of(0, {0, 1, 5});
  for (int d : held_of(1, {0, 1, 3, 4, 5})) held.push_back(d);
  const Vector q = system.initial_state();
  const std::vector<FreeMotion> free = free_of(system, q, held, Eigen::Vector3d(0, 0, 1));
  ASSERT_EQ(free.size(), 1u);
  EXPECT_EQ(free[0].rotation.norm(), 0.0);
  EXPECT_NEAR(free[0].translation.z(), 1.0, 1e-12);
  EXPECT_EQ(describe_free_motions(free, Eigen::Vector3d::Zero()), "translation along (0, 0, 1)");
  // Holding the sphere's z as well leaves nothing free.
  held.push_back(6 + 2);
  EXPECT_TRUE(free_of(system, q, held, Eigen::Vector3d(0, 0, 1)).empty());
}

// A body whose centre is held keeps its three rotations about that centre, wherever the
// rotations are measured from; the description names the axis through the centre.
TEST(FreeMotions, HeldCentreLeavesRotationsAboutIt) {
  const RigidBodySystem full = testing::box_on_ground(Eigen::Vector3d(4, 4, 1), Eigen::Vector3d(1, 1, 1), 1.0,
                                                      Eigen::Vector2d(0.5, -0.25), Eigen::Vector3d(0.4, 0, 0));
  const RigidBodySystem system({full.body(1)});
  const Vector q = system.initial_state();
  const std::vector<FreeMotion> free = free_of(system, q, held_of(0, {0, 1, 2}), Eigen::Vector3d(3, 2, 1));
  ASSERT_EQ(free.size(), 3u);
  const Eigen::Vector3d centre = q.head<3>(), c(3, 2, 1);
  for (const FreeMotion& m : free) {
    ASSERT_GT(m.rotation.norm(), 0.0);
    // The centre does not move: u + a x (T - c) = 0; the described axis passes through it.
    EXPECT_LT((m.translation + m.rotation.cross(centre - c)).norm(), 1e-9);
    const Eigen::Vector3d point = c + m.rotation.cross(m.translation) / m.rotation.squaredNorm();
    EXPECT_LT((centre - point).cross(m.rotation.normalized()).norm(), 1e-9);
  }
  EXPECT_EQ(describe_free_motions({free[0]}, c).rfind("rotation about (", 0), 0u);
}

}  // namespace
}  // namespace tailor::rigid::free_motions_test
