// The private rotation-variant SVD helper: F = U diag(sigma) V^T, U and V proper rotations,
// sigma ordered by magnitude with the reflection on the smallest one.
#include "forward/fem/materials/rotation_variant_svd.hpp"

#include <gtest/gtest.h>

#include "tests/forward/fem_materials/material_test_support.hpp"

namespace tailor::test::rotation_variant_svd_test {
namespace {

template <class T>
class RotationVariantSvdTest : public ::testing::Test {};
using Dims = ::testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(RotationVariantSvdTest, Dims);

TYPED_TEST(RotationVariantSvdTest, ReconstructsWithProperRotations) {
  constexpr int Dim = TypeParam::value;
  auto cases = deformation_cases<Dim>();
  cases.push_back({"zero", Mat<Dim>::Zero()});
  cases.push_back({"identity", Mat<Dim>::Identity()});
  Mat<Dim> reflection = Mat<Dim>::Identity();
  reflection(0, 0) = -1.0;
  cases.push_back({"reflection", reflection});
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    material_detail::RotationVariantSvd<Dim> svd;
    material_detail::rotation_variant_svd(c.F, svd);
    const double scale = std::max(1.0, c.F.norm());
    EXPECT_LE((svd.U * svd.sigma.asDiagonal() * svd.V.transpose() - c.F).norm(), 1e-13 * scale);
    EXPECT_LE((svd.U.transpose() * svd.U - Mat<Dim>::Identity()).norm(), 1e-13);
    EXPECT_LE((svd.V.transpose() * svd.V - Mat<Dim>::Identity()).norm(), 1e-13);
    EXPECT_NEAR(svd.U.determinant(), 1.0, 1e-13);
    EXPECT_NEAR(svd.V.determinant(), 1.0, 1e-13);
    for (int i = 0; i + 1 < Dim; ++i) {
      EXPECT_GE(svd.sigma(i), std::abs(svd.sigma(i + 1)) - 1e-14 * scale);
      EXPECT_GE(svd.sigma(i), 0.0);
    }
    EXPECT_EQ(svd.sigma(Dim - 1) < 0.0, c.F.determinant() < -1e-15);
  }
}

}  // namespace
}  // namespace tailor::test::rotation_variant_svd_test
