#pragma once
// Discrete adjoint of reduced implicit dynamics (forward/reduction/reduced_dynamics.hpp):
// the gradient of a trajectory objective
//
//   J = sum_{n=0}^{N} j_n(q_n)
//
// with respect to z = [q0 (r), v0 (r), alpha, beta, s]: initial coordinates and velocities,
// Rayleigh coefficients and the material scale. One forward simulation, then one backward
// sweep over the stored states; each step's adjoint solves with that step's Newton Jacobian
// (dense, r x r, re-evaluated at the stored q_{n+1}). Exact for the discrete scheme (not an
// approximation of the continuous adjoint), so Taylor tests see rate 2.
#include <memory>
#include <vector>

#include "adjoint/reduced_functional.hpp"
#include "forward/reduction/reduced_dynamics.hpp"

namespace tailor {

// One term j_n(q_n) per stored state n = 0..N, in reduced coordinates (the full-space trajectory
// objectives are objectives/trajectory_objective.hpp).
class ReducedTrajectoryObjective {
 public:
  virtual ~ReducedTrajectoryObjective() = default;
  // j_n(q); gradient (size r, overwritten) when non-null.
  virtual double evaluate(int n, const Vector& q, Vector* gradient) const = 0;
};

// 1/2 |rows q_n - targets[n]|^2 / (N + 1), rows e.g. from vertex_rows(): tracks chosen vertices'
// displacements (or q itself with rows = I). targets: N + 1 vectors of size rows.rows().
class TrackedDisplacements final : public ReducedTrajectoryObjective {
 public:
  TrackedDisplacements(Matrix rows, std::vector<Vector> targets);
  double evaluate(int n, const Vector& q, Vector* gradient) const override;

 private:
  Matrix rows_;
  std::vector<Vector> targets_;
};

class ReducedDynamicsFunctional final : public ReducedFunctional {
 public:
  // options: integrator, time step and Newton settings (its alpha, beta, s are replaced by z).
  ReducedDynamicsFunctional(const ReducedElasticModel& model, ReducedDynamicsOptions options, Matrix mass,
                            Vector external_force, int steps,
                            std::shared_ptr<const ReducedTrajectoryObjective> objective);
  static Vector pack(const Vector& q0, const Vector& v0, double alpha, double beta, double scale);

  int size() const override { return 2 * model_.size() + 3; }
  double value(const Vector& z) override;
  double value_and_gradient(const Vector& z, Vector& gradient) override;
  const ReducedTrajectory& last_trajectory() const { return trajectory_; }

 private:
  ReducedDynamics dynamics(const Vector& z) const;
  double forward(const Vector& z);
  const ReducedElasticModel& model_;
  ReducedDynamicsOptions options_;
  Matrix mass_;
  Vector external_force_;
  int steps_;
  std::shared_ptr<const ReducedTrajectoryObjective> objective_;
  ReducedTrajectory trajectory_;
};

}  // namespace tailor
