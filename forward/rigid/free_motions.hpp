#pragma once
// Common rigid motions that a static problem's supports leave free. A static equilibrium needs
// every motion of the whole assembly as one rigid body (3 translations, 3 rotations) to be
// stopped by a held DOF: contact, elasticity and joints resist only relative motion, so a free
// common motion makes the Hessian singular and, with a load along it, the energy unbounded
// (Newton then takes huge steps or stalls). FEM scenes have this check for meshes
// (forward/reduction/free_space.hpp); this is the one for rigid bodies and rods.
//
// A motion is given by its DOF velocities: column k of `motions` (num_dofs x 6) for the unit
// translation along axis k (k < 3) and the unit rotation about axis k - 3 through `centre`
// (k >= 3), i.e. a point p moves at u + a x (p - centre).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "forward/core/types.hpp"
#include "forward/rigid/rigid_body_system.hpp"

namespace tailor::rigid {

// One free common motion: points move at translation + rotation x (p - centre).
struct FreeMotion {
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d rotation = Eigen::Vector3d::Zero();  // zero: a pure translation
};

// A basis of the combinations of the six motions that no DOF in `held` feels (relative
// tolerance 1e-10; `length` scales the rotations against the translations: the assembly's
// size). Pure translations first, then the rest (rotations about some axis, with the
// translation that puts the axis where it is).
std::vector<FreeMotion> free_motions(const Matrix& motions, const std::vector<int>& held, double length);

// "translation along (0, 0, 1); rotation about (1, 0, 0) through (0, 0, 0.5)".
std::string describe_free_motions(const std::vector<FreeMotion>& free, const Eigen::Vector3d& centre);

// The six common motions of a rigid body system at state q (size num_dofs >= 6 B): each body's
// T moves with its centre, its rotation vector w by J(w)^-1 a (dR R^T = [J dw]); `points` are
// further DOFs that move as material points, (first DOF, position), e.g. FEM vertices.
Matrix rigid_system_motions(const RigidBodySystem& system, const Vector& q, int num_dofs,
                            const std::vector<std::pair<int, Eigen::Vector3d>>& points,
                            const Eigen::Vector3d& centre);

}  // namespace tailor::rigid
