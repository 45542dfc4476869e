// Mass properties of a closed triangle mesh (see mass_properties.hpp).
#include "forward/rigid/mass_properties.hpp"

#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

namespace tailor::rigid {

MassProperties mass_properties(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces,
                               double density) {
  if (!(density > 0.0) || !std::isfinite(density))
    throw std::invalid_argument("mass_properties: density must be positive, got " + std::to_string(density));
  std::map<std::pair<int, int>, int> directed;
  for (int f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = faces(f, k), b = faces(f, (k + 1) % 3);
      if (a < 0 || a >= vertices.rows() || b < 0 || b >= vertices.rows())
        throw std::invalid_argument("mass_properties: face " + std::to_string(f) +
                                    " refers to a missing vertex");
      ++directed[{a, b}];
    }
  for (const auto& [edge, count] : directed) {
    const auto twin = directed.find({edge.second, edge.first});
    if (count != 1 || twin == directed.end() || twin->second != 1)
      throw std::invalid_argument(
          "mass_properties: the mesh is not closed and consistently oriented at edge (" +
          std::to_string(edge.first) + ", " + std::to_string(edge.second) + ")");
  }
  double volume = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (int f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3d a = vertices.row(faces(f, 0)), b = vertices.row(faces(f, 1)),
                          c = vertices.row(faces(f, 2));
    const double v = a.dot(b.cross(c)) / 6.0;
    const Eigen::Vector3d sum = a + b + c;
    volume += v;
    first += v * sum / 4.0;
    second += v / 20.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + sum * sum.transpose());
  }
  if (!(volume > 0.0))
    throw std::invalid_argument("mass_properties: non-positive enclosed volume " + std::to_string(volume) +
                                " (faces oriented inward?)");
  MassProperties m;
  m.volume = volume;
  m.mass = density * volume;
  m.center = first / volume;
  // Second moment about the centre, then I = tr(C) Id - C.
  const Eigen::Matrix3d C = density * second - m.mass * m.center * m.center.transpose();
  m.inertia = C.trace() * Eigen::Matrix3d::Identity() - C;
  return m;
}

}  // namespace tailor::rigid
