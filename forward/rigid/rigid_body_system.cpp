// Rigid body DOFs, world positions and primitive surfaces (see rigid_body_system.hpp).
#include "forward/rigid/rigid_body_system.hpp"

#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

#include "forward/rigid/mass_properties.hpp"

namespace tailor::rigid {

RigidBody rigid_body_from_mesh(std::string name, const Eigen::MatrixX3d& world_vertices,
                               const Eigen::MatrixX3i& faces, double density, bool fixed) {
  const MassProperties m = mass_properties(world_vertices, faces, density);
  RigidBody body;
  body.name = std::move(name);
  body.vertices = world_vertices.rowwise() - m.center.transpose();
  body.faces = faces;
  body.mass = m.mass;
  body.inertia = m.inertia;
  body.position = m.center;
  body.fixed = fixed;
  return body;
}

void box_surface(const Eigen::Vector3d& size, Eigen::MatrixX3d& vertices, Eigen::MatrixX3i& faces) {
  vertices.resize(8, 3);
  for (int i = 0; i < 8; ++i)
    vertices.row(i) << (i & 1 ? 0.5 : -0.5) * size.x(), (i & 2 ? 0.5 : -0.5) * size.y(),
        (i & 4 ? 0.5 : -0.5) * size.z();
  faces.resize(12, 3);
  faces << 0, 2, 1, 1, 2, 3,  // z-
      4, 5, 6, 5, 7, 6,       // z+
      0, 1, 4, 1, 5, 4,       // y-
      2, 6, 3, 3, 6, 7,       // y+
      0, 4, 2, 2, 4, 6,       // x-
      1, 3, 5, 3, 7, 5;       // x+
}

void sphere_surface(double radius, int subdivisions, Eigen::MatrixX3d& vertices, Eigen::MatrixX3i& faces) {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                                    {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                                    {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  std::vector<Eigen::Vector3i> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& p : v) p.normalize();
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      const auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      v.push_back((v[static_cast<std::size_t>(a)] + v[static_cast<std::size_t>(b)]).normalized());
      return midpoint[key] = static_cast<int>(v.size()) - 1;
    };
    std::vector<Eigen::Vector3i> refined;
    for (const auto& t : f) {
      const int ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
      refined.push_back({t[0], ab, ca});
      refined.push_back({t[1], bc, ab});
      refined.push_back({t[2], ca, bc});
      refined.push_back({ab, bc, ca});
    }
    f = std::move(refined);
  }
  vertices.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i)
    vertices.row(static_cast<Eigen::Index>(i)) = radius * v[i].transpose();
  faces.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t i = 0; i < f.size(); ++i) faces.row(static_cast<Eigen::Index>(i)) = f[i].transpose();
}

RigidBodySystem::RigidBodySystem(std::vector<RigidBody> bodies) : bodies_(std::move(bodies)) {
  int total = 0;
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const RigidBody& body = bodies_[b];
    if (body.vertices.rows() == 0)
      throw std::invalid_argument("rigid body " + std::to_string(b) + " (" + body.name + ") has no vertices");
    if (!(body.mass > 0.0))
      throw std::invalid_argument("rigid body " + std::to_string(b) + " (" + body.name + ") has mass " +
                                  std::to_string(body.mass));
    total += static_cast<int>(body.vertices.rows());
  }
  Eigen::MatrixX3i faces(0, 3);
  std::vector<int> groups;
  int offset = 0;
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const RigidBody& body = bodies_[b];
    const Eigen::Index rows = faces.rows();
    faces.conservativeResize(rows + body.faces.rows(), 3);
    faces.bottomRows(body.faces.rows()) = body.faces.array() + offset;
    for (int i = 0; i < body.vertices.rows(); ++i) {
      vertex_body_.push_back(static_cast<int>(b));
      vertex_local_.push_back(i);
      groups.push_back(body.fixed ? -1 : static_cast<int>(b));  // fixed bodies never meet each other
    }
    offset += static_cast<int>(body.vertices.rows());
  }
  surface_ = contact::ContactSurface::from_faces(total, faces, groups);
}

Vector RigidBodySystem::initial_state() const {
  Vector q(num_dofs());
  for (int b = 0; b < num_bodies(); ++b) {
    q.segment<3>(6 * b) = body(b).position;
    q.segment<3>(6 * b + 3) = body(b).rotation;
  }
  return q;
}

std::vector<int> RigidBodySystem::fixed_dofs() const {
  std::vector<int> dofs;
  for (int b = 0; b < num_bodies(); ++b)
    if (body(b).fixed || body(b).kinematic)
      for (int k = 0; k < 6; ++k) dofs.push_back(6 * b + k);
  return dofs;
}

bool RigidBodySystem::has_kinematic() const {
  for (const RigidBody& b : bodies_)
    if (b.kinematic) return true;
  return false;
}

Vector RigidBodySystem::prescribed_state(double t, const Vector& q) const {
  Vector out = q;
  for (int b = 0; b < num_bodies(); ++b) {
    const RigidBody& body = this->body(b);
    if (!body.kinematic) continue;
    out.segment<3>(6 * b) = body.position + t * body.kinematic_velocity;
    const Eigen::Matrix3d R =
        rotation_matrix(t * body.kinematic_angular_velocity) * rotation_matrix(body.rotation);
    const Eigen::Vector3d w = rotation_vector(R, q.segment<3>(6 * b + 3));
    out.segment<3>(6 * b + 3) = w;
  }
  return out;
}

contact::Positions RigidBodySystem::world_positions(const Vector& q) const {
  if (q.size() != num_dofs())
    throw std::invalid_argument("rigid bodies: state of size " + std::to_string(q.size()) + ", expected " +
                                std::to_string(num_dofs()));
  contact::Positions x(surface_.num_vertices, 3);
  int row = 0;
  for (int b = 0; b < num_bodies(); ++b) {
    const Eigen::Matrix3d R = rotation_matrix(q.segment<3>(6 * b + 3));
    const Eigen::Vector3d T = q.segment<3>(6 * b);
    for (int i = 0; i < body(b).vertices.rows(); ++i)
      x.row(row++) = (T + R * body(b).vertices.row(i).transpose()).transpose();
  }
  return x;
}

}  // namespace tailor::rigid
