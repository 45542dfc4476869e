// Rodrigues' rotation and its exact first and second derivatives, near zero (series), at
// moderate angles, across the series/closed-form switch and near pi; the reference for R is
// Eigen's AngleAxis, for the derivatives central differences.
#include "forward/rigid/rotation.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

namespace tailor::rigid::rotation_test {
namespace {

const Eigen::Vector3d kAxis = Eigen::Vector3d(1, -2, 3).normalized();

class RotationAtAngle : public ::testing::TestWithParam<double> {};

TEST_P(RotationAtAngle, MatchesAngleAxisWithExactDerivatives) {
  const double angle = GetParam();
  const Eigen::Vector3d w = angle * kAxis;
  const RotationDerivatives r = rotation_derivatives(w);
  const Eigen::Matrix3d reference = Eigen::AngleAxisd(angle, kAxis).toRotationMatrix();
  EXPECT_LT((r.rotation - reference).norm(), 1e-14);
  EXPECT_LT((rotation_matrix(w) - reference).norm(), 1e-14);
  EXPECT_LT((r.rotation.transpose() * r.rotation - Eigen::Matrix3d::Identity()).norm(), 1e-14);
  const double h = 1e-5;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d e = h * Eigen::Vector3d::Unit(k);
    const Eigen::Matrix3d dR = (rotation_matrix(w + e) - rotation_matrix(w - e)) / (2 * h);
    EXPECT_LT((r.first[k] - dR).norm(), 1e-9) << "k=" << k;
    for (int l = 0; l < 3; ++l) {
      const Eigen::Matrix3d d2R =
          (rotation_derivatives(w + e).first[l] - rotation_derivatives(w - e).first[l]) / (2 * h);
      EXPECT_LT((r.second[k][l] - d2R).norm(), 1e-8) << "k=" << k << " l=" << l;
      EXPECT_LT((r.second[k][l] - r.second[l][k]).norm(), 1e-15);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Angles, RotationAtAngle,
                         ::testing::Values(0.0, 1e-12, 1e-7, 1e-3, 0.3, 1.0 - 1e-10, 1.0 + 1e-10, 2.0, 3.0,
                                           M_PI - 1e-7, M_PI + 0.2));

TEST(Rotation, DerivativesAtZeroAreTheGenerators) {
  // dR/dw_k at 0 is [e_k]; d2R/dw_k dw_l at 0 is ([e_k][e_l] + [e_l][e_k]) / 2.
  auto hat = [](const Eigen::Vector3d& v) {
    Eigen::Matrix3d K;
    K << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
    return K;
  };
  const RotationDerivatives r = rotation_derivatives(Eigen::Vector3d::Zero());
  for (int k = 0; k < 3; ++k) {
    EXPECT_LT((r.first[k] - hat(Eigen::Vector3d::Unit(k))).norm(), 1e-16);
    for (int l = 0; l < 3; ++l) {
      const Eigen::Matrix3d expected = 0.5 * (hat(Eigen::Vector3d::Unit(k)) * hat(Eigen::Vector3d::Unit(l)) +
                                              hat(Eigen::Vector3d::Unit(l)) * hat(Eigen::Vector3d::Unit(k)));
      EXPECT_LT((r.second[k][l] - expected).norm(), 1e-16);
    }
  }
}

TEST(Rotation, CoefficientsAreContinuousAcrossTheSeriesSwitch) {
  const RodriguesCoefficients below = rodrigues_coefficients(1.0 - 1e-13),
                              above = rodrigues_coefficients(1.0 + 1e-13);
  EXPECT_NEAR(below.a, above.a, 1e-13);
  EXPECT_NEAR(below.da, above.da, 1e-13);
  EXPECT_NEAR(below.d2a, above.d2a, 1e-12);
  EXPECT_NEAR(below.b, above.b, 1e-13);
  EXPECT_NEAR(below.db, above.db, 1e-13);
  EXPECT_NEAR(below.d2b, above.d2b, 1e-12);
  // Limits at 0: a = 1, a' = -1/6, a'' = 2/120; b = 1/2, b' = -1/24, b'' = 2/720.
  const RodriguesCoefficients zero = rodrigues_coefficients(0.0);
  EXPECT_DOUBLE_EQ(zero.a, 1.0);
  EXPECT_DOUBLE_EQ(zero.da, -1.0 / 6.0);
  EXPECT_DOUBLE_EQ(zero.d2a, 2.0 / 120.0);
  EXPECT_DOUBLE_EQ(zero.b, 0.5);
  EXPECT_DOUBLE_EQ(zero.db, -1.0 / 24.0);
  EXPECT_DOUBLE_EQ(zero.d2b, 2.0 / 720.0);
}

}  // namespace
}  // namespace tailor::rigid::rotation_test
