// DiscreteRod: bad input, and the tracking of the reference twist across many updates. When one
// edge's tangent precesses around a cone of half-angle alpha while its neighbour stays fixed, the
// time-parallel director comes back rotated by the enclosed solid angle 2 pi (1 - cos alpha) per
// turn (the holonomy of parallel transport on the sphere, Berry/Hannay phase), so the reference
// twist must grow by that amount each turn, past pi, without jumping back by 2 pi.
#include "forward/rods/discrete_rod.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace tailor::discrete_rod_test {
namespace {

TEST(DiscreteRod, BadInputIsRejectedWithContext) {
  Eigen::MatrixX3d one(1, 3);
  one << 0, 0, 0;
  EXPECT_THROW(DiscreteRod(one, 0, 3), std::invalid_argument);
  Eigen::MatrixX3d repeated(3, 3);
  repeated << 0, 0, 0, 1, 0, 0, 1, 0, 0;
  try {
    DiscreteRod rod(repeated, 0, 9);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("edge 1"), std::string::npos) << e.what();
  }
  Eigen::MatrixX3d line(3, 3);
  line << 0, 0, 0, 1, 0, 0, 2, 0, 0;
  EXPECT_THROW(DiscreteRod(line, 0, 5), std::invalid_argument);  // twists overlap positions
  EXPECT_THROW(DiscreteRod(line, -1, 9), std::invalid_argument);
}

TEST(DiscreteRod, ReferenceTwistTracksManyTurnsOfHolonomy) {
  const double alpha = M_PI / 3.0;  // holonomy pi per turn
  auto direction = [&](double phi) {
    return Eigen::Vector3d(std::cos(alpha), std::sin(alpha) * std::cos(phi), std::sin(alpha) * std::sin(phi));
  };
  Eigen::MatrixX3d pts(3, 3);
  pts.row(0) << -1, 0, 0;
  pts.row(1) << 0, 0, 0;
  pts.row(2) = direction(0.0).transpose();
  DiscreteRod rod(pts, 0, 9);
  Vector x = Vector::Zero(rod.dof_end());
  rod.write_rest_state(x);
  const double start = rod.reference_twist(x, 0);
  const int steps_per_turn = 400, turns = 3;
  for (int s = 1; s <= steps_per_turn * turns; ++s) {
    x.segment<3>(6) = direction(2.0 * M_PI * s / steps_per_turn);
    rod.update_reference_frames(x);
    if (s % steps_per_turn == 0) {
      const int k = s / steps_per_turn;
      const double expected = k * 2.0 * M_PI * (1.0 - std::cos(alpha));
      EXPECT_NEAR(std::abs(rod.stored_reference_twist(0) - start), expected, 1e-3 * expected) << "turn " << k;
    }
  }
}

}  // namespace
}  // namespace tailor::discrete_rod_test
