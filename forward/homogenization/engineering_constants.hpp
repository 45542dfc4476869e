#pragma once
// Engineering constants of an effective tensor in Voigt notation (convention of
// linear_homogenization.hpp: engineering shear strains, plain stresses), from the compliance
// S = (C^H)^-1 (docs/methods.md section 12; e.g. Nye, Physical Properties of Crystals, ch. VIII):
//   E(d)      = 1 / ((d d^T) : S : (d d^T))              directional Young's modulus
//   nu(d, n)  = -((n n^T) : S : (d d^T)) / ((d d^T) : S : (d d^T)),  n orthogonal to d
//   G(d, n)   = 1 / ((d n^T + n d^T) : S : (d n^T + n d^T))  shear modulus in the (d, n) plane
// In 2D plane strain these are the in-plane (plane-strain) constants, e.g. E(d) = E / (1 - nu^2)
// and nu = nu / (1 - nu) for an isotropic phase; in plane stress they are the plate's E and nu.
#include "forward/core/types.hpp"

namespace tailor {

// The Voigt vector (plain stress convention) of the symmetric tensor T (dim x dim).
Vector voigt_stress(const Matrix& T);
// The symmetric tensor of a Voigt strain vector (engineering shear halved).
Matrix strain_from_voigt(const Vector& voigt);

// S = C^-1; throws std::invalid_argument when C is not square of size 3 or 6, or singular.
Matrix compliance(const Matrix& stiffness);
double directional_youngs_modulus(const Matrix& compliance, const Vector& d);
double poisson_ratio(const Matrix& compliance, const Vector& d, const Vector& n);
double shear_modulus(const Matrix& compliance, const Vector& d, const Vector& n);

// Isotropic stiffness (Voigt) of a phase with Young's modulus E and Poisson's ratio nu: 3D,
// 2D plane strain, or 2D plane stress.
Matrix isotropic_stiffness(int dim, double youngs_modulus, double poisson_ratio, bool plane_stress = false);

// The unit direction at angle theta (radians) in the (e_i, e_j) plane of dimension dim.
Vector plane_direction(int dim, int i, int j, double theta);

}  // namespace tailor
