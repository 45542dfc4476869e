#pragma once
// Tori as rigid bodies with an implicit surface (docs/tori.md).
//
// A torus of major radius R and tube semi-axes r (radial) and r1 (along the axis), 0 < r < R,
// r1 > 0, in its body frame: the surface
//   V(u, v) = ((R + r cos v) cos u, (R + r cos v) sin u, r1 sin v),
// the body z axis its axis of symmetry, the centre of mass at the origin; the solid is
//   g(x) = (rho / r)^2 + (z / r1)^2 - 1 <= 0,   rho = sqrt(x^2 + y^2) - R.
// Its core circle is c(theta) = R (cos theta, sin theta, 0); in the world, at the rigid DOFs
// (T, w) of forward/rigid (translation, rotation vector), c(theta) = T + R Q(w) (cos theta,
// sin theta, 0), Q(w) the Rodrigues rotation. A circular tube (r1 = r) is the solid of points
// within r of the core (torus_distance.hpp uses that); an elliptic one (r1 != r) is not, and
// its distance is a surface-surface minimization (elliptic_distance.hpp).
#include <Eigen/Core>

#include "forward/rigid/rigid_body_system.hpp"

namespace tailor::tori {

struct TorusShape {
  double major_radius = 1.0;  // R [length]
  double minor_radius = 0.25;  // r [length], 0 < r < R: the tube's radial semi-axis
  // r1 [length]: the tube's semi-axis along the body z axis; 0 means equal to minor_radius (a
  // circular tube that stays circular when minor_radius changes, e.g. as a design parameter).
  double minor_radius_1 = 0.0;
};

// r1 (minor_radius when minor_radius_1 is 0).
double axial_radius(const TorusShape& shape);
// r1 != r: the surface-surface distance of elliptic_distance.hpp applies.
bool is_elliptic(const TorusShape& shape);
// R + max(r, r1): every surface point lies within it of the centre (bounding spheres, CCD).
double bounding_radius(const TorusShape& shape);

// Throws std::invalid_argument unless 0 < r < R and r1 = 0 or r1 > 0 (all finite); `where`
// names the input.
void validate_shape(const TorusShape& shape, const std::string& where);

// Solid torus of density rho with an elliptic cross-section E (semi-axes r radial, r1 axial;
// area A = pi r r1): by Pappus m = rho 2 pi R A = rho 2 pi^2 R r r1. Inertia about the centre in
// the body frame, integrating over E with rho_ax = R + s the distance from the axis
// (dV = 2 pi rho_ax ds dz, int_E s = int_E s^3 = 0, int_E s^2 = A r^2 / 4, int_E z^2 = A r1^2 / 4):
//   I_zz = rho int 2 pi rho_ax^3 = m (R^2 + 3 r^2 / 4),
//   int z^2 dm = rho int 2 pi rho_ax z^2 = m r1^2 / 4,   int x^2 dm = int y^2 dm = I_zz / 2,
//   I_xx = I_yy = m (R^2 / 2 + 3 r^2 / 8 + r1^2 / 4),
// which for r1 = r is the circular m (R^2/2 + 5 r^2/8), m (R^2 + 3 r^2/4) (used as written then).
double torus_mass(const TorusShape& shape, double density);
Eigen::Matrix3d torus_inertia(const TorusShape& shape, double mass);

// A closed, outward triangulation in the body frame: `major` rings of `minor` vertices.
//  inscribed = false: the vertices on the torus surface (a mesh for mesh IPC and output);
//  inscribed = true: every triangle lies inside the solid torus, so implicit tori apart =>
//    these meshes apart (the intersection check of the tests).
//    Circular: the tube radius shrunk by the sag R (1 - cos(pi / major)) of the core's chords (a
//    point of a triangle is within r - sag of a point of the chord triangle of the core, which
//    is within the sag of the core).
//    Elliptic: the cross-section E scaled about its centre by k = 1 - (R + r) c / r, c = 1 -
//    cos(pi / major). A triangle's point is x = l p + (1 - l) q with p, q on the scaled sections
//    kE of its two rings (each section is convex), i.e. at (s, z) = l (s_p, z_p) + (1 - l)
//    (s_q, z_q) in kE, horizontally the combination of two vectors of lengths R + s_p, R + s_q at
//    the angle 2 pi / major: its distance from the axis lies in [(R + s) cos(pi / major), R + s],
//    so x's section coordinates are (s - e, z) with 0 <= e <= (R + r) c = (1 - k) r. And kE + a
//    radial shift by at most (1 - k) r lies in kE + (1 - k) E = E (E convex, symmetric): x lies
//    in the solid. Needs (R + r) c < r (enough major segments; else invalid_argument).
void torus_surface(const TorusShape& shape, int major, int minor, bool inscribed, Eigen::MatrixX3d& vertices,
                   Eigen::MatrixX3i& faces);

// A rigid body for the torus: closed-form mass and inertia (not the mesh's), the given mesh as
// its vertices (output, the velocity bound of the rigid stepper, the intersection check).
rigid::RigidBody torus_body(std::string name, const TorusShape& shape, double density,
                            const Eigen::Vector3d& position, const Eigen::Vector3d& rotation, bool fixed,
                            int major_segments, int minor_segments, bool inscribed);

}  // namespace tailor::tori
