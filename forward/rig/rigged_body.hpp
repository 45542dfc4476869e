#pragma once
// A tet mesh driven by a rig, simulated on its moving rest shape (Xu & Barbic 2016, section 4;
// Li, Xu & Barbic 2016 for the fixed region): with u the displacement measured from the rigged
// shape X(p(t)) (world positions x = X(p(t)) + u),
//
//   M u'' + alpha M u' + f_int(X(p(t)); X(p(t)) + u) = f_ext + f_inert,   f_inert = -M d2X/dt2,
//
// which is Newton's law for x exactly; f_int is the hyperelastic force of the mesh whose rest
// shape is X(p(t)) (every element's rest volume and shape gradients follow the rig), and the
// mass matrix is that of the bind pose (mass belongs to material points). Vertices of the fixed
// region follow the rig (u = 0). Units: SI-consistent, time in s, alpha in 1/s.
#include <memory>
#include <string>
#include <vector>

#include "forward/core/model.hpp"
#include "forward/fem/material.hpp"
#include "forward/mesh/mesh.hpp"
#include "forward/rig/pose_trajectory.hpp"

namespace tailor {

struct RiggedBody {
  Mesh mesh;                           // tets; rest_positions = the rig's bind pose
  MaterialKind material = MaterialKind::stvk;
  Vector youngs_modulus, poisson_ratio, density;  // per element
  std::vector<int> fixed_vertices;     // follow the rig exactly
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  // f_ext = M gravity [length / s^2]
};

// The parameters p = [E_e; nu_e] of the elastic term of a body.
Vector rigged_body_parameters(const RiggedBody& body);

// The mesh with its rest positions replaced by rest_shape (3 per vertex, stacked): the rigged
// shape at one pose as a rest shape.
Mesh posed_mesh(const Mesh& mesh, const Vector& rest_shape);
// The elastic Model of the body at rest shape X (3n interleaved): one ElasticTerm with E at
// p[0, ne) and nu at p[ne, 2 ne), the fixed vertices eliminated (held at X).
Model rigged_elastic_model(const RiggedBody& body, const Vector& rest_shape);
// The free DOFs (not in a fixed vertex), increasing.
std::vector<int> rigged_free_dofs(const RiggedBody& body);

struct MovingRestOptions {
  double time_step = 1e-2;      // h [s], > 0
  double rayleigh_mass = 0.0;   // alpha [1/s], >= 0
  bool inertial_forces = true;  // false: the rig moves the rest shape kinematically
  int max_newton_iterations = 30;
  double newton_tolerance = 1e-10;  // on the free residual relative to the sum of its parts' norms (inertial, elastic, applied)
};

struct MovingRestState {
  double time = 0.0;
  Vector u, v;  // displacement from X(p(t)) and its rate, 3n
};

// Full-space implicit Euler on u: each step minimizes
//   c / (2 h^2) |u' - u - h v / c|_M^2 + E(X(p(t')); X(p(t')) + u') - (f_ext + f_inert(t'))^T u',
// c = 1 + alpha h, by Newton (exact Hessian, projected when the exact one is indefinite) with a
// backtracking line search, CHOLMOD on the free DOFs.
class MovingRestDynamics {
 public:
  MovingRestDynamics(const Rig& rig, RiggedBody body, MovingRestOptions options);
  ~MovingRestDynamics();

  MovingRestState initial_state(double time = 0.0) const;
  bool step(const PoseTrajectory& trajectory, const MovingRestState& current, MovingRestState& next,
            int& iterations, std::string& message) const;

  const SparseMatrix& mass() const { return mass_; }
  const RiggedBody& body() const { return body_; }
  const Rig& rig() const { return rig_; }
  const MovingRestOptions& options() const { return options_; }
  // f_ext + f_inert at a motion, 3n (zero on no DOF: the fixed rows are ignored by the solve).
  Vector applied_force(const PoseMotion& motion) const;

 private:
  const Rig& rig_;
  RiggedBody body_;
  MovingRestOptions options_;
  SparseMatrix mass_;
  Vector params_, gravity_force_;
  std::vector<int> free_dofs_;
};

}  // namespace tailor
