// free_rod_motions (forward/rods/rod_supports.hpp): the rigid motions a rod's supports leave
// free. Reference: by hand (a clamp holds every motion; one pin leaves the three rotations
// about it; two pins on a straight rod leave the spin about its axis, which turns every
// material frame, unless an edge's twist is held too).
#include "forward/rods/rod_supports.hpp"

#include <gtest/gtest.h>

#include "rod_fixtures.hpp"

namespace tailor::rod_supports_test {
namespace {

using namespace tailor::testing;

std::vector<rigid::FreeMotion> free_of(const RodSetup& s, const std::vector<int>& held) {
  Eigen::Vector3d centre;
  return free_rod_motions({s.rod.get()}, s.rest, held, centre);
}

TEST(RodSupports, FreeMotionsOfClampedPinnedAndFreeRods) {
  const RodSetup bent = make_rod(helix(8, 1.0, 0.2, 0.4));
  EXPECT_EQ(free_of(bent, {}).size(), 6u);
  EXPECT_TRUE(free_of(bent, clamped_end_dofs(*bent.rod, RodEnd::last)).empty());
  const std::vector<rigid::FreeMotion> pinned = free_of(bent, pinned_vertex_dofs(*bent.rod, 3));
  ASSERT_EQ(pinned.size(), 3u);
  for (const rigid::FreeMotion& m : pinned) {
    ASSERT_GT(m.rotation.norm(), 0.0);  // rotations about the pin: the pin does not move
    Eigen::Vector3d centre;
    free_rod_motions({bent.rod.get()}, bent.rest, {}, centre);
    EXPECT_LT((m.translation + m.rotation.cross(bent.rod->position(bent.rest, 3) - centre)).norm(), 1e-9);
  }
  // A straight rod pinned at both ends spins about its axis (positions still, twists turning).
  const RodSetup bar = make_rod(straight(6, 2.0));
  std::vector<int> pins = pinned_vertex_dofs(*bar.rod, 0);
  for (int d : pinned_vertex_dofs(*bar.rod, 5)) pins.push_back(d);
  const std::vector<rigid::FreeMotion> spin = free_of(bar, pins);
  ASSERT_EQ(spin.size(), 1u);
  Eigen::Vector3d centre;
  free_rod_motions({bar.rod.get()}, bar.rest, pins, centre);
  EXPECT_EQ(rigid::describe_free_motions(spin, centre), "rotation about (1, 0, 0) through (1, 0, 0)");
  pins.push_back(bar.rod->twist_dof(2));
  EXPECT_TRUE(free_of(bar, pins).empty());
  // The same pins on a bent rod: it turns about the line through them.
  std::vector<int> bent_pins = pinned_vertex_dofs(*bent.rod, 0);
  for (int d : pinned_vertex_dofs(*bent.rod, 7)) bent_pins.push_back(d);
  EXPECT_EQ(free_of(bent, bent_pins).size(), 1u);
}

}  // namespace
}  // namespace tailor::rod_supports_test
