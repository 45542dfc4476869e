// Mass properties from closed meshes against the closed forms of a solid box
// (I = m/12 diag(b^2+c^2, a^2+c^2, a^2+b^2)) and a solid sphere (I = 2/5 m r^2).
#include "forward/rigid/mass_properties.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "forward/rigid/rigid_body_system.hpp"

namespace tailor::rigid::mass_properties_test {
namespace {

TEST(MassProperties, BoxMatchesClosedFormAnywhere) {
  Eigen::MatrixX3d v;
  Eigen::MatrixX3i f;
  box_surface(Eigen::Vector3d(1, 2, 3), v, f);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 1, 2).normalized()).toRotationMatrix();
  const Eigen::Vector3d c(0.3, -1.0, 2.0);
  const Eigen::MatrixX3d moved = ((v * R.transpose()).rowwise() + c.transpose()).eval();
  const MassProperties m = mass_properties(moved, f, 2.0);
  EXPECT_NEAR(m.volume, 6.0, 1e-12);
  EXPECT_NEAR(m.mass, 12.0, 1e-12);
  EXPECT_LT((m.center - c).norm(), 1e-12);
  const Eigen::Matrix3d expected = R * Eigen::Vector3d(13, 10, 5).asDiagonal() * R.transpose();
  EXPECT_LT((m.inertia - expected).norm(), 1e-11);
}

TEST(MassProperties, IcosphereApproachesSolidSphere) {
  Eigen::MatrixX3d v;
  Eigen::MatrixX3i f;
  sphere_surface(2.0, 4, v, f);
  const MassProperties m = mass_properties(v, f, 1.0);
  const double volume = 4.0 / 3.0 * M_PI * 8.0;
  EXPECT_NEAR(m.volume / volume, 1.0, 5e-3);  // inscribed polyhedron: slightly smaller
  EXPECT_LT(m.volume, volume);
  EXPECT_NEAR(m.inertia(0, 0) / (0.4 * m.mass * 4.0), 1.0, 1e-2);
  EXPECT_LT(m.center.norm(), 1e-12);
}

TEST(MassProperties, RejectsOpenOrInvertedMeshes) {
  Eigen::MatrixX3d v;
  Eigen::MatrixX3i f;
  box_surface(Eigen::Vector3d(1, 1, 1), v, f);
  EXPECT_THROW(mass_properties(v, f.topRows(11), 1.0), std::invalid_argument);
  Eigen::MatrixX3i inverted = f;
  inverted.col(1).swap(inverted.col(2));
  EXPECT_THROW(mass_properties(v, inverted, 1.0), std::invalid_argument);
  EXPECT_THROW(mass_properties(v, f, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::rigid::mass_properties_test
