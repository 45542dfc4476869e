#pragma once
// Mass, centre of mass and inertia tensor of a homogeneous solid bounded by a closed,
// consistently oriented (outward) triangle mesh, by the divergence theorem: the solid is the
// signed sum of the tetrahedra (0, a, b, c) over faces (a, b, c), each with
//   volume V = a . (b x c) / 6,   integral of x = V (a + b + c) / 4,
//   integral of x x^T = V / 20 (a a^T + b b^T + c c^T + (a + b + c)(a + b + c)^T).
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace tailor::rigid {

struct MassProperties {
  double volume = 0.0;                                // [length^3]
  double mass = 0.0;                                  // density * volume [mass]
  Eigen::Vector3d center = Eigen::Vector3d::Zero();   // centre of mass [length]
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // about the centre [mass length^2]
};

// `vertices` n x 3, `faces` m x 3 (outward orientation), density > 0 [mass / length^3].
// Throws std::invalid_argument when the mesh is not closed and consistently oriented (every
// directed edge must have exactly one reversed twin), has a non-positive volume, or the
// density is not positive.
MassProperties mass_properties(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces,
                               double density);

}  // namespace tailor::rigid
