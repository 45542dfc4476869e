// Torus shape, mass properties and triangulation (see torus.hpp).
#include "forward/tori/torus.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tailor::tori {

double axial_radius(const TorusShape& shape) {
  return shape.minor_radius_1 == 0.0 ? shape.minor_radius : shape.minor_radius_1;
}

bool is_elliptic(const TorusShape& shape) { return axial_radius(shape) != shape.minor_radius; }

double bounding_radius(const TorusShape& shape) {
  return shape.major_radius + std::max(shape.minor_radius, axial_radius(shape));
}

void validate_shape(const TorusShape& shape, const std::string& where) {
  const double R = shape.major_radius, r = shape.minor_radius, r1 = shape.minor_radius_1;
  if (!std::isfinite(R) || !std::isfinite(r) || !(r > 0.0) || !(r < R))
    throw std::invalid_argument(where + ": a torus needs 0 < minor_radius < major_radius, got R = " +
                                std::to_string(R) + ", r = " + std::to_string(r));
  if (!std::isfinite(r1) || !(r1 >= 0.0))
    throw std::invalid_argument(where +
                                ": a torus needs minor_radius_1 > 0 (or 0: equal to minor_radius), got " +
                                std::to_string(r1));
}

double torus_mass(const TorusShape& shape, double density) {
  const double R = shape.major_radius, r = shape.minor_radius, r1 = axial_radius(shape);
  return density * 2.0 * M_PI * M_PI * R * r * r1;
}

Eigen::Matrix3d torus_inertia(const TorusShape& shape, double mass) {
  const double R = shape.major_radius, r = shape.minor_radius, r1 = axial_radius(shape);
  const double side = is_elliptic(shape) ? mass * (0.5 * R * R + 0.375 * r * r + 0.25 * r1 * r1)
                                         : mass * (0.5 * R * R + 0.625 * r * r);
  const double axis = mass * (R * R + 0.75 * r * r);
  return Eigen::Vector3d(side, side, axis).asDiagonal();
}

void torus_surface(const TorusShape& shape, int major, int minor, bool inscribed, Eigen::MatrixX3d& vertices,
                   Eigen::MatrixX3i& faces) {
  if (major < 3 || minor < 3)
    throw std::invalid_argument("torus_surface: at least 3 segments each way, got " + std::to_string(major) +
                                " x " + std::to_string(minor));
  const double R = shape.major_radius;
  double r = shape.minor_radius, r1 = axial_radius(shape);
  if (inscribed && !is_elliptic(shape)) {
    r -= R * (1.0 - std::cos(M_PI / major));
    r1 = r;
  } else if (inscribed) {
    const double k = 1.0 - (R + r) * (1.0 - std::cos(M_PI / major)) / r;  // torus.hpp
    if (!(k > 0.0))
      throw std::invalid_argument("torus_surface: " + std::to_string(major) +
                                  " major segments are too few for an inscribed elliptic tube of R = " +
                                  std::to_string(R) + ", r = " + std::to_string(r));
    r *= k;
    r1 *= k;
  }
  vertices.resize(major * minor, 3);
  faces.resize(2 * major * minor, 3);
  for (int i = 0; i < major; ++i) {
    const double theta = 2.0 * M_PI * i / major;
    for (int j = 0; j < minor; ++j) {
      const double phi = 2.0 * M_PI * j / minor;
      const double rho = R + r * std::cos(phi);
      vertices.row(i * minor + j) << rho * std::cos(theta), rho * std::sin(theta), r1 * std::sin(phi);
    }
  }
  int f = 0;
  for (int i = 0; i < major; ++i)
    for (int j = 0; j < minor; ++j) {
      const int a = i * minor + j, b = ((i + 1) % major) * minor + j, c = ((i + 1) % major) * minor + (j + 1) % minor,
                d = i * minor + (j + 1) % minor;
      // Outward: theta grows to b, phi grows to d; (b - a) x (d - a) points out of the tube.
      faces.row(f++) << a, b, c;
      faces.row(f++) << a, c, d;
    }
}

rigid::RigidBody torus_body(std::string name, const TorusShape& shape, double density,
                            const Eigen::Vector3d& position, const Eigen::Vector3d& rotation, bool fixed,
                            int major_segments, int minor_segments, bool inscribed) {
  validate_shape(shape, name);
  if (!(density > 0.0) || !std::isfinite(density))
    throw std::invalid_argument(name + ": density must be positive, got " + std::to_string(density));
  rigid::RigidBody body;
  body.name = std::move(name);
  torus_surface(shape, major_segments, minor_segments, inscribed, body.vertices, body.faces);
  body.mass = torus_mass(shape, density);
  body.inertia = torus_inertia(shape, body.mass);
  body.position = position;
  body.rotation = rotation;
  body.fixed = fixed;
  return body;
}

}  // namespace tailor::tori
