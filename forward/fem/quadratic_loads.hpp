#pragma once
// Consistent nodal loads on quadratic meshes (forward/mesh/quadratic_mesh.hpp), dead loads on
// the rest configuration, for an ExternalForceTerm (forward/fem/loads.hpp):
//   f_a = int_facet N_a t dA        (tractions)        f_a = int_element N_a rho g dV  (gravity)
// with the P2 shape functions of the facet or element. Unlike lumping, the weights of a P2
// facet are not equal: a straight edge of length l under a uniform traction t gives l t / 6 to
// each end and 2 l t / 3 to its middle node; a flat triangle of area A gives 0 to its corners
// and A t / 3 to each edge node; a straight-sided tet of volume V gives -V/20 rho g to each
// corner and V/5 rho g to each edge node (Zienkiewicz & Taylor, Vol. 1, sections 8.8 and 9.5).
// Facets are integrated with the segment's 3-point Gauss rule (2D, degree 5) or the triangle's
// degree-4 rule (3D). That is exact on straight facets, and for the pressure on curved
// (isoparametric) ones too: N_a times the area-weighted normal dX/dxi rotated (degree 1) or
// dX/dxi x dX/deta (degree 2) is a polynomial of degree 3 or 4. A uniform traction on a curved
// facet weighs N_a with |dX/dxi|, no polynomial: there the rules are accurate, not exact.
#include "forward/core/types.hpp"
#include "forward/mesh/quadratic_mesh.hpp"

namespace tailor {

// A uniform traction t [force / area] (size dim) on quadratic facets (rows of 3 nodes in 2D,
// 6 in 3D, as from quadratic_facets).
Vector quadratic_traction_forces(const QuadraticMesh& mesh, const Eigen::MatrixXi& facets,
                                 const Eigen::VectorXd& traction);

// A uniform pressure p [force / area] on quadratic facets: the traction -p n with n the outward
// unit normal of the rest facet (facets oriented as boundary_facets: positive p pushes inwards).
Vector quadratic_pressure_forces(const QuadraticMesh& mesh, const Eigen::MatrixXi& facets, double pressure);

// Gravity: density per element [mass / volume], acceleration g (size dim), integrated with the
// degree-2 rule of the elements (exact on straight-sided elements).
Vector quadratic_gravity_forces(const QuadraticMesh& mesh, const Eigen::VectorXd& density,
                                const Eigen::VectorXd& gravity);

}  // namespace tailor
