#include "forward/meshless/analytic_shape.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tailor {

namespace {

// Exact signed distance of an axis-aligned box of half-extents b centred at c.
double box_distance(const Eigen::Vector3d& X, const Eigen::Vector3d& c, const Eigen::Vector3d& b) {
  const Eigen::Vector3d q = (X - c).cwiseAbs() - b;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

}  // namespace

AnalyticShape box_shape(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  if (!(lo.array() < hi.array()).all()) throw std::invalid_argument("box_shape: needs lo < hi in every coordinate");
  AnalyticShape s;
  s.name = "box";
  const Eigen::Vector3d c = 0.5 * (lo + hi), b = 0.5 * (hi - lo);
  s.signed_distance = [c, b](const Eigen::Vector3d& X) { return box_distance(X, c, b); };
  s.lo = lo;
  s.hi = hi;
  s.exact_volume = (hi - lo).prod();
  return s;
}

AnalyticShape sphere_shape(const Eigen::Vector3d& center, double radius) {
  if (!(radius > 0.0)) throw std::invalid_argument("sphere_shape: the radius must be positive");
  AnalyticShape s;
  s.name = "sphere";
  s.signed_distance = [center, radius](const Eigen::Vector3d& X) { return (X - center).norm() - radius; };
  s.lo = center.array() - radius;
  s.hi = center.array() + radius;
  s.exact_volume = 4.0 / 3.0 * M_PI * radius * radius * radius;
  return s;
}

AnalyticShape cylinder_shape(const Eigen::Vector3d& center, double radius, double length, int axis) {
  if (!(radius > 0.0) || !(length > 0.0)) throw std::invalid_argument("cylinder_shape: radius and length must be positive");
  if (axis < 0 || axis > 2) throw std::invalid_argument("cylinder_shape: axis must be 0, 1 or 2, not " + std::to_string(axis));
  AnalyticShape s;
  s.name = "cylinder";
  s.signed_distance = [center, radius, length, axis](const Eigen::Vector3d& X) {
    const Eigen::Vector3d d = X - center;
    const double along = d[axis];
    const double radial = std::sqrt(std::max(0.0, d.squaredNorm() - along * along));
    // The 2D box distance in (radial, axial): exact for the solid of revolution.
    const double qr = radial - radius, qa = std::abs(along) - 0.5 * length;
    return std::hypot(std::max(qr, 0.0), std::max(qa, 0.0)) + std::min(std::max(qr, qa), 0.0);
  };
  s.lo = center.array() - radius;
  s.hi = center.array() + radius;
  s.lo[axis] = center[axis] - 0.5 * length;
  s.hi[axis] = center[axis] + 0.5 * length;
  s.exact_volume = M_PI * radius * radius * length;
  return s;
}

AnalyticShape shell_octant_shape(const Eigen::Vector3d& center, double inner_radius, double outer_radius) {
  if (!(inner_radius > 0.0) || !(outer_radius > inner_radius))
    throw std::invalid_argument("shell_octant_shape: needs 0 < inner_radius < outer_radius");
  AnalyticShape s;
  s.name = "shell_octant";
  s.signed_distance = [center, inner_radius, outer_radius](const Eigen::Vector3d& X) {
    const Eigen::Vector3d d = X - center;
    const double r = d.norm();
    return std::max({r - outer_radius, inner_radius - r, -d[0], -d[1], -d[2]});
  };
  s.lo = center;
  s.hi = center.array() + outer_radius;
  s.exact_volume = M_PI / 6.0 * (outer_radius * outer_radius * outer_radius - inner_radius * inner_radius * inner_radius);
  return s;
}

}  // namespace tailor
