// Elliptic tubes (r1 != r): mass and inertia against the divergence-theorem integral of a fine
// surface mesh (forward/rigid/mass_properties), the circular formulas unchanged, and the
// inscribed triangulation inside the solid (the on-surface one is not: the check can fail).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "forward/rigid/mass_properties.hpp"
#include "forward/tori/elliptic_distance.hpp"
#include "forward/tori/torus.hpp"

namespace tailor::tori::elliptic_shape_test {
namespace {

TEST(EllipticTorusShape, MassAndInertiaMatchTheMeshIntegral) {
  // Reference: the solid bounded by a 400 x 200 triangulation, integrated exactly by the
  // divergence theorem (an inscribed polyhedron: converges at second order in the segments).
  for (const TorusShape shape : {TorusShape{1.0, 0.2, 0.35}, TorusShape{1.5, 0.4, 0.1}}) {
    const double density = 1000.0;
    Eigen::MatrixX3d V;
    Eigen::MatrixX3i F;
    torus_surface(shape, 400, 200, false, V, F);
    const rigid::MassProperties mesh = rigid::mass_properties(V, F, density);
    const double m = torus_mass(shape, density);
    const Eigen::Matrix3d I = torus_inertia(shape, m);
    EXPECT_NEAR(mesh.mass / m, 1.0, 5e-4);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(mesh.inertia(k, k) / I(k, k), 1.0, 5e-4) << k;
    EXPECT_NEAR(mesh.inertia(0, 1), 0.0, 1e-9 * I(0, 0));
    // The circular side inertia m (R^2/2 + 5 r^2/8) would be far off: the check can fail.
    const double R = shape.major_radius, r = shape.minor_radius;
    EXPECT_GT(std::abs(mesh.inertia(0, 0) / (m * (0.5 * R * R + 0.625 * r * r)) - 1.0), 1e-2);
  }
}

TEST(EllipticTorusShape, CircularShapesKeepTheirFormulas) {
  const TorusShape unset{1.0, 0.2}, equal{1.0, 0.2, 0.2};
  EXPECT_FALSE(is_elliptic(unset));
  EXPECT_FALSE(is_elliptic(equal));
  EXPECT_EQ(torus_mass(unset, 1000.0), 1000.0 * 2.0 * M_PI * M_PI * 1.0 * 0.2 * 0.2);
  EXPECT_EQ(torus_inertia(equal, 3.0), torus_inertia(unset, 3.0));
  EXPECT_EQ(torus_inertia(unset, 3.0)(0, 0), 3.0 * (0.5 + 0.625 * 0.04));
  EXPECT_EQ(bounding_radius(TorusShape{1.0, 0.2, 0.35}), 1.35);
  EXPECT_THROW(validate_shape(TorusShape{1.0, 0.2, -0.1}, "test"), std::invalid_argument);
  EXPECT_THROW(validate_shape(TorusShape{1.0, 0.2, NAN}, "test"), std::invalid_argument);
}

// Largest g (torus.hpp) over the vertices and 15 barycentric points of every face.
double largest_implicit(const TorusShape& shape, const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F) {
  const TorusPose pose{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), shape};
  double worst = -std::numeric_limits<double>::infinity();
  for (int f = 0; f < F.rows(); ++f)
    for (int i = 0; i <= 4; ++i)
      for (int j = 0; i + j <= 4; ++j) {
        const Eigen::Vector3d x =
            (i * V.row(F(f, 0)) + j * V.row(F(f, 1)) + (4 - i - j) * V.row(F(f, 2))).transpose() / 4.0;
        worst = std::max(worst, implicit_value(pose, x));
      }
  return worst;
}

TEST(EllipticTorusShape, InscribedMeshLiesInsideTheSolid) {
  for (const TorusShape shape : {TorusShape{1.0, 0.2, 0.35}, TorusShape{1.0, 0.3, 0.12}})
    for (int major : {16, 24, 48}) {
      Eigen::MatrixX3d V;
      Eigen::MatrixX3i F;
      torus_surface(shape, major, 8, true, V, F);
      EXPECT_LT(largest_implicit(shape, V, F), 0.0) << major;
      // On the surface, the chords of the inner equator stick out.
      torus_surface(shape, major, 8, false, V, F);
      EXPECT_GT(largest_implicit(shape, V, F), 0.0) << major;
    }
  Eigen::MatrixX3d V;
  Eigen::MatrixX3i F;
  EXPECT_THROW(torus_surface(TorusShape{1.0, 0.05, 0.2}, 6, 8, true, V, F), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::tori::elliptic_shape_test
