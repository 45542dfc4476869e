#pragma once
// Bending stiffness of a plate-like cell (docs/methods.md section 12, "Bending"): a 3D cell periodic
// along a_1, a_2 (in the x-y plane) with free faces across its thickness. A macro curvature
// kappa (2 x 2, symmetric) is imposed by the Kirchhoff field about the mid-plane z = z_m,
//   u_a = -(z - z_m) kappa_ab x_b,   u_z = 1/2 kappa_ab x_a x_b    (a, b in {x, y}),
// plus a fluctuation periodic in x and y (free across the thickness); the periodic rotations
// of the seed are the increments of this field between paired faces. The cell energy per unit
// area is 1/2 kappa^T D kappa (Voigt (11, 22, 12) with engineering twist 2 kappa_12), so
//   D_IJ = (1/A) u_I^T K u_J,   A = |a_1 x a_2|,
// from 3 unit curvatures sharing one factorization, and b(d) = k(d)^T D k(d) with k(d) the
// Voigt curvature of d d^T (the seed's (d d^T) : B : (d d^T)). D refers to the mid-plane and
// to zero mean membrane strain.
#include "forward/core/types.hpp"
#include "forward/homogenization/periodic_cell.hpp"

namespace tailor {

struct PlateBending {
  Matrix stiffness;  // D (3 x 3), moment per unit length per unit curvature
  double mid_plane = 0.0;
  double factorization_seconds = 0.0;
};

// Needs a 3D cell with periodic == {true, true, false}, a_1 and a_2 in the x-y plane. Per-element
// Young's modulus and Poisson's ratio. Throws std::invalid_argument otherwise.
PlateBending plate_bending_stiffness(const PeriodicCell& cell, const Vector& youngs_modulus,
                                     const Vector& poisson_ratio);
// b(d) = k(d)^T D k(d), k(d) = (d_x^2, d_y^2, 2 d_x d_y), d a unit in-plane direction.
double directional_bending_stiffness(const Matrix& plate_stiffness, const Vector& d);

}  // namespace tailor
