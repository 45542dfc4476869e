#pragma once
// Supports, loads and masses of a discrete elastic rod, in the forms the existing Model takes:
// lists of fixed DOFs for Elimination::dirichlet, and nodal force vectors (interleaved like the
// state; a "force" on a twist DOF is a twisting moment about the edge's tangent) for
// ExternalForceTerm (forward/fem/loads.hpp), whose potential is -f . x.
#include <vector>

#include "forward/rigid/free_motions.hpp"
#include "forward/rods/cross_section.hpp"
#include "forward/rods/discrete_rod.hpp"

namespace tailor {

enum class RodEnd { first, last };

// Clamp: the two end vertices and the end edge's twist (position and frame held).
std::vector<int> clamped_end_dofs(const DiscreteRod& rod, RodEnd end);
// Pin: the three coordinates of one vertex (rotation free). Throws std::out_of_range.
std::vector<int> pinned_vertex_dofs(const DiscreteRod& rod, int vertex);

// Lumped vertex masses [mass]: each edge's rho A(r_j) L_j split equally between its vertices.
// density [mass / length^3]; radius and rest_length per edge.
Eigen::VectorXd lumped_vertex_masses(const DiscreteRod& rod, const CrossSection& section, double density,
                                     const Eigen::VectorXd& radius, const Eigen::VectorXd& rest_length);

// Twist inertias [mass length^2] of the edges: rho (I1 + I2)(r_j) L_j, the polar moment of area
// of the section times the edge's rest length (the kinetic energy of the section spinning about
// the tangent at rate dtheta/dt: with the time-parallel reference frame, which does not spin
// about the tangent, dtheta/dt is the material frame's angular velocity about it). For a circle
// I1 + I2 = J = pi r^4 / 2.
Eigen::VectorXd lumped_twist_inertias(const DiscreteRod& rod, const CrossSection& section, double density,
                                      const Eigen::VectorXd& radius, const Eigen::VectorXd& rest_length);
// diagonal[position DOFs of vertex v] = vertex mass, diagonal[twist DOF of edge j] = twist
// inertia (the two functions above): the rod's slice of a lumped diagonal mass (MassOperator's
// fixed-diagonal form). Other entries are left unchanged.
void add_rod_mass_diagonal(const DiscreteRod& rod, const CrossSection& section, double density,
                           const Eigen::VectorXd& radius, const Eigen::VectorXd& rest_length, Vector& diagonal);

// forces += m_v g on every vertex (g [length / time^2], masses from lumped_vertex_masses).
void add_gravity_forces(const DiscreteRod& rod, const Eigen::VectorXd& vertex_masses,
                        const Eigen::Vector3d& g, Vector& forces);
// forces += F on one vertex [force].
void add_point_load(const DiscreteRod& rod, int vertex, const Eigen::Vector3d& force, Vector& forces);
// forces += M on one edge's twist DOF: a twisting moment about the tangent [force length].
// The potential -M theta^j is a function of the state only while the reference frames stay
// where they were (theta is measured from the stored frame): a driver that updates them
// between solves needs RodTwistingMomentTerm (twisting_moment_term.hpp) instead.
void add_twisting_moment(const DiscreteRod& rod, int edge, double moment, Vector& forces);

// The rigid motions of a group of rods moving as one body (positions u + a x (x - centre),
// each edge's twist by a . t^j, its material frame turning with the body) that the `held` DOFs
// leave free, at state x (rigid::free_motions; a pinned joint inside the group ties positions
// that move alike anyway). Empty when the supports hold the group. `centre`: the group's
// bounding-box centre, for rigid::describe_free_motions.
std::vector<rigid::FreeMotion> free_rod_motions(const std::vector<const DiscreteRod*>& rods, const Vector& x,
                                                const std::vector<int>& held, Eigen::Vector3d& centre);

}  // namespace tailor
