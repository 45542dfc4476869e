#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstdio>

namespace tailor::eigen_test {
namespace {

TEST(smoke, EigenSolvesSmallSpdSystem) {
  Eigen::Matrix3d a;
  a << 4, 1, 0,  //
      1, 3, 1,   //
      0, 1, 2;
  const Eigen::Vector3d expected(1.0, -2.0, 3.0);
  const Eigen::Vector3d x = a.llt().solve(a * expected);
  EXPECT_LT((x - expected).norm(), 1e-14);
  std::printf("Eigen %d.%d.%d\n", EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION);
}

}  // namespace
}  // namespace tailor::eigen_test
