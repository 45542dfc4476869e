#pragma once
// Rigid bodies as DOFs (docs/methods.md section 10): body b owns q_b = (T_b, w_b) at DOFs
// 6b..6b+5 (translation [length], rotation vector [rad]); its vertices are
//   x = T_b + R(w_b) V,
// V the body-frame position relative to the centre of mass. The surfaces of all bodies form
// one ContactSurface whose groups are the bodies (a body never collides with itself; fixed
// bodies share one group: they never move, so they never meet each other).
#include <string>
#include <vector>

#include "forward/contact/contact_surface.hpp"
#include "forward/core/types.hpp"
#include "forward/rigid/rotation.hpp"

namespace tailor::rigid {

struct RigidBody {
  std::string name;
  Eigen::MatrixX3d vertices;                              // body frame, centre of mass at the origin [length]
  Eigen::MatrixX3i faces;                                 // outward triangles
  double mass = 1.0;                                      // [mass]
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Identity();  // about the centre, body frame
  Eigen::Vector3d position = Eigen::Vector3d::Zero();     // initial T (centre of mass)
  Eigen::Vector3d rotation = Eigen::Vector3d::Zero();     // initial w
  bool fixed = false;  // a fixed body's DOFs are meant to be eliminated (fixed_dofs())
  // A kinematic body follows a prescribed motion: its DOFs are eliminated like a fixed body's,
  // but its pose at time t is T(t) = position + t kinematic_velocity and
  // R(t) = exp([t kinematic_angular_velocity]) R(rotation) (world frame; prescribed_state()).
  bool kinematic = false;
  Eigen::Vector3d kinematic_velocity = Eigen::Vector3d::Zero();          // [length / time]
  Eigen::Vector3d kinematic_angular_velocity = Eigen::Vector3d::Zero();  // [rad / time]
};

// A body from a closed mesh in world coordinates with a density: mass, centre and inertia
// from mass_properties(); vertices moved to the body frame, position = the centre.
RigidBody rigid_body_from_mesh(std::string name, const Eigen::MatrixX3d& world_vertices,
                               const Eigen::MatrixX3i& faces, double density, bool fixed = false);
// The closed surface of an axis-aligned box of the given full size, centred at the origin.
void box_surface(const Eigen::Vector3d& size, Eigen::MatrixX3d& vertices, Eigen::MatrixX3i& faces);
// An icosphere of the given radius (subdivisions >= 0), centred at the origin.
void sphere_surface(double radius, int subdivisions, Eigen::MatrixX3d& vertices, Eigen::MatrixX3i& faces);

class RigidBodySystem {
 public:
  // Throws std::invalid_argument on a body without vertices or with a non-positive mass.
  explicit RigidBodySystem(std::vector<RigidBody> bodies);

  int num_bodies() const { return static_cast<int>(bodies_.size()); }
  int num_dofs() const { return 6 * num_bodies(); }
  const RigidBody& body(int b) const { return bodies_[static_cast<std::size_t>(b)]; }
  const std::vector<RigidBody>& bodies() const { return bodies_; }

  Vector initial_state() const;         // (T_b, w_b) of every body
  std::vector<int> fixed_dofs() const;  // the 6 DOFs of each fixed or kinematic body
  bool has_kinematic() const;
  // `q` with every kinematic body at its pose at time t; its rotation vector is the one of that
  // rotation nearest to q's (so that consecutive poses are joined by short paths in w).
  Vector prescribed_state(double t, const Vector& q) const;

  // All bodies' surfaces as one, surface vertex i = vertex local_index(i) of body body_of(i).
  const contact::ContactSurface& surface() const { return surface_; }
  int body_of(int surface_vertex) const { return vertex_body_[static_cast<std::size_t>(surface_vertex)]; }
  int local_index(int surface_vertex) const {
    return vertex_local_[static_cast<std::size_t>(surface_vertex)];
  }
  // Body-frame position of a surface vertex.
  Eigen::Vector3d body_frame(int surface_vertex) const {
    return body(body_of(surface_vertex)).vertices.row(local_index(surface_vertex)).transpose();
  }

  // World positions of all surface vertices at state q.
  contact::Positions world_positions(const Vector& q) const;

 private:
  std::vector<RigidBody> bodies_;
  contact::ContactSurface surface_;
  std::vector<int> vertex_body_, vertex_local_;
};

}  // namespace tailor::rigid
