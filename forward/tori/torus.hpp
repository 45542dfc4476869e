#pragma once
// Tori as rigid bodies with an implicit surface (docs/tori.md).
//
// A torus of major radius R and tube (minor) radius r, R > r > 0, in its body frame: the solid
// of points within r of its core circle
//   c(theta) = R (cos theta, sin theta, 0),
// the body z axis its axis of symmetry, the centre of mass at the origin. In the world, at the
// rigid DOFs (T, w) of forward/rigid (translation, rotation vector):
//   c(theta) = T + R Q(w) (cos theta, sin theta, 0),   Q(w) the Rodrigues rotation.
// Only circular tubes: an elliptic tube (r1 != r) is not supported (its offset surface is not
// the set of points within one radius of the core, so the distance below would not hold).
#include <Eigen/Core>

#include "forward/rigid/rigid_body_system.hpp"

namespace tailor::tori {

struct TorusShape {
  double major_radius = 1.0;  // R [length]
  double minor_radius = 0.25; // r [length], 0 < r < R
};

// Throws std::invalid_argument unless 0 < r < R (both finite); `where` names the input.
void validate_shape(const TorusShape& shape, const std::string& where);

// Solid torus of density rho: m = rho 2 pi^2 R r^2, inertia about the centre in the body frame
// diag(m (R^2/2 + 5 r^2/8), m (R^2/2 + 5 r^2/8), m (R^2 + 3 r^2/4)).
double torus_mass(const TorusShape& shape, double density);
Eigen::Matrix3d torus_inertia(const TorusShape& shape, double mass);

// A closed, outward triangulation in the body frame: `major` rings of `minor` vertices.
//  inscribed = false: the vertices on the torus surface (a mesh for mesh IPC and output);
//  inscribed = true: the tube radius shrunk by the sag R (1 - cos(pi / major)) of the core's
//    chords, so every triangle lies inside the solid torus (a point of a triangle is within
//    r - sag of a point of the chord triangle of the core, which is within the sag of the core):
//    implicit tori apart => these meshes apart (the intersection check of the tests).
void torus_surface(const TorusShape& shape, int major, int minor, bool inscribed, Eigen::MatrixX3d& vertices,
                   Eigen::MatrixX3i& faces);

// A rigid body for the torus: closed-form mass and inertia (not the mesh's), the given mesh as
// its vertices (output, the velocity bound of the rigid stepper, the intersection check).
rigid::RigidBody torus_body(std::string name, const TorusShape& shape, double density,
                            const Eigen::Vector3d& position, const Eigen::Vector3d& rotation, bool fixed,
                            int major_segments, int minor_segments, bool inscribed);

}  // namespace tailor::tori
