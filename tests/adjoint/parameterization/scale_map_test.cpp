// scale_map: p = diag(s) z, against the closed form and differences; a wrong scale is rejected.
#include "map_checks.hpp"

namespace tailor::scale_map_test {
namespace {

using testing::random_vector;

TEST(ScaleMap, IsTheDiagonalScaling) {
  const Vector scales = (Vector(4) << 1e-3, 2.0, -0.5, 1e4).finished();
  const auto map = scale_map(scales);
  EXPECT_EQ(map->name(), "scale(4)");
  const Vector z = random_vector(4, 7);
  EXPECT_TRUE(map->apply(z).isApprox(scales.cwiseProduct(z), 1e-15));
  EXPECT_TRUE(map->jacobian(z).isApprox(Matrix(scales.asDiagonal()), 1e-15));
  testing::expect_first_order_consistent(*map, z, false);
  testing::expect_linear_in_z(*map, z);
  EXPECT_THROW(scale_map((Vector(2) << 1.0, 0.0).finished()), std::invalid_argument);
  EXPECT_THROW(scale_map((Vector(1) << std::nan("")).finished()), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::scale_map_test
