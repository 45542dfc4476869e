// The independent interpenetration check (see interpenetration_check.hpp).
#include "forward/interlocking/interpenetration_check.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace tailor::interlocking {
namespace {

// The rotation matrix of a rotation vector, written out here (Rodrigues' formula) so that the
// check does not use the rigid-body code it checks.
Eigen::Matrix3d rotation_of(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle == 0.0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

}  // namespace

void core_distance_bounds(const Eigen::Vector3d& Ta, const Eigen::Vector3d& wa, double Ra, const Eigen::Vector3d& Tb,
                          const Eigen::Vector3d& wb, double Rb, int samples, double& lower, double& upper) {
  const Eigen::Matrix3d Qa = rotation_of(wa), Qb = rotation_of(wb);
  const Eigen::Vector3d n = Qb.col(2);
  double best = std::numeric_limits<double>::infinity();
  const double h = 2.0 * M_PI / samples;
  for (int k = 0; k < samples; ++k) {
    const double t = h * k;
    const Eigen::Vector3d p = Ta + Ra * (std::cos(t) * Qa.col(0) + std::sin(t) * Qa.col(1));
    const Eigen::Vector3d v = p - Tb;
    const double z = v.dot(n);
    const double rho = (v - z * n).norm();
    best = std::min(best, std::hypot(z, rho - Rb));
  }
  upper = best;
  lower = best - 0.5 * Ra * h;
}

ClearanceReport check_clearance(const PeriodicRigidCell& cell, const Vector& x, int samples) {
  ClearanceReport report;
  double range = std::numeric_limits<double>::infinity();
  for (const CellElement& e : cell.spec().elements) range = std::min(range, 0.1 * e.shape.major_radius);
  report.min_lower = std::numeric_limits<double>::infinity();
  const int nb = cell.num_bodies();
  for (int a = 0; a < nb; ++a)
    for (int b = a + 1; b < nb; ++b) {
      if (a >= cell.num_elements() && b >= cell.num_elements()) continue;  // image-image: another cell's pair
      const tori::TorusShape& sa = cell.spec().elements[static_cast<std::size_t>(cell.master(a))].shape;
      const tori::TorusShape& sb = cell.spec().elements[static_cast<std::size_t>(cell.master(b))].shape;
      const Eigen::Vector3d Ta = x.segment<3>(6 * a), Tb = x.segment<3>(6 * b);
      const double ra1 = sa.minor_radius_1 > 0.0 ? sa.minor_radius_1 : sa.minor_radius;
      const double rb1 = sb.minor_radius_1 > 0.0 ? sb.minor_radius_1 : sb.minor_radius;
      // Bounding spheres more than `range` apart certify the pair by themselves (their gap is a
      // lower bound); closer pairs are sampled.
      const double sphere_gap = (Ta - Tb).norm() - (sa.major_radius + std::max(sa.minor_radius, ra1) +
                                                    sb.major_radius + std::max(sb.minor_radius, rb1));
      if (sphere_gap >= range) continue;
      if (ra1 != sa.minor_radius || rb1 != sb.minor_radius) {
        report.elliptic_skipped = true;
        continue;
      }
      PairClearance c;
      c.body_a = a;
      c.body_b = b;
      double lower = 0.0, upper = 0.0;
      core_distance_bounds(Ta, x.segment<3>(6 * a + 3), sa.major_radius, Tb, x.segment<3>(6 * b + 3), sb.major_radius,
                           samples, lower, upper);
      c.upper = upper - sa.minor_radius - sb.minor_radius;
      c.lower = lower - sa.minor_radius - sb.minor_radius;
      report.min_lower = std::min(report.min_lower, c.lower);
      report.pairs.push_back(c);
    }
  return report;
}

}  // namespace tailor::interlocking
