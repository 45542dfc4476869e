#pragma once
// Analytic solids for the meshless simulator (docs/meshless.md): a signed distance
// d(X) (negative inside, zero on the boundary) and a bounding box. The node placement and the
// clipped quadrature (octree_sampling.hpp) rely on d being 1-Lipschitz with |d(X)| no larger
// than the distance from X to the boundary, so that a cell whose centre has |d| above its
// half-diagonal lies wholly on one side. The signed distances below have that property.
#include <Eigen/Core>
#include <functional>
#include <string>

namespace tailor {

struct AnalyticShape {
  std::string name;
  std::function<double(const Eigen::Vector3d&)> signed_distance;
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();  // bounding box
  double exact_volume = 0.0;  // 0 where unknown (implicit surfaces)
  // Optional: a value whose sign decides inside (<= 0) more finely than signed_distance, which
  // then only classifies cells (implicit_surface.hpp); empty for the analytic shapes.
  std::function<double(const Eigen::Vector3d&)> inside_value;
  double inside_measure(const Eigen::Vector3d& X) const { return inside_value ? inside_value(X) : signed_distance(X); }
  bool inside(const Eigen::Vector3d& X) const { return inside_measure(X) <= 0.0; }
};

// Axis-aligned box [lo, hi]. std::invalid_argument unless lo < hi componentwise.
AnalyticShape box_shape(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);
// Ball of the given centre and radius > 0.
AnalyticShape sphere_shape(const Eigen::Vector3d& center, double radius);
// Solid circular cylinder along coordinate axis `axis` (0, 1, 2) through `center`, radius and
// length > 0 (flat caps at center +- length / 2 along the axis).
AnalyticShape cylinder_shape(const Eigen::Vector3d& center, double radius, double length, int axis = 2);

// The octant x, y, z >= 0 of the spherical shell inner_radius <= |X - center| <= outer_radius
// (0 < inner < outer), for problems with three symmetry planes. Its signed distance is the
// maximum of the shell's and the three half-spaces': exact inside, a lower bound of the distance
// outside, which is what the sampling needs.
AnalyticShape shell_octant_shape(const Eigen::Vector3d& center, double inner_radius, double outer_radius);

}  // namespace tailor
