#pragma once
// Implicit Euler time stepping of rigid bodies (docs/methods.md section 1): each step minimizes the
// incremental potential (RigidInertiaTerm + the model's other terms: gravity, loads, IPC
// contact) by Newton, whose line search starts from the contact term's CCD step, so every
// accepted step is intersection-free; then v = (T_{n+1} - T_n) / h, Rdot = (R_{n+1} - R_n) / h.
// Rotation vectors are wrapped to |w| <= pi between steps (same rotation), away from the
// parameterization's singularity at 2 pi.
#include <vector>

#include "forward/core/model.hpp"
#include "forward/rigid/rigid_inertia_term.hpp"
#include "forward/solve/newton.hpp"

namespace tailor::rigid {

class RigidTimeStepper {
 public:
  // `model` holds `inertia` and the other terms over the system's DOFs; all must outlive the
  // stepper. Starts from the bodies' initial poses at rest.
  RigidTimeStepper(const RigidBodySystem& system, Model& model, RigidInertiaTerm& inertia,
                   NewtonOptions options = {});

  // One step; on a Newton failure the state is left unchanged and the result says why.
  NewtonResult step();
  const Vector& state() const { return q_; }
  const std::vector<RigidMotion>& motion() const { return motion_; }
  void set_velocity(int body, const Eigen::Vector3d& velocity, const Eigen::Vector3d& angular_velocity);

 private:
  const RigidBodySystem& system_;
  Model& model_;
  RigidInertiaTerm& inertia_;
  NewtonSolver newton_;
  Vector q_;
  std::vector<RigidMotion> motion_;
};

}  // namespace tailor::rigid
