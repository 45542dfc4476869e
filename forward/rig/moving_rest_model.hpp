#pragma once
// The dynamics on the moving rest shape (rigged_body.hpp) as a Model for the generic time
// integrator (forward/dynamics/time_integrator.hpp), so that the transient adjoint
// (adjoint/transient_functional.hpp) differentiates a rigged body's trajectory with respect to
// its material parameters. The state is u, the displacement from the rigged shape X(p(t))
// (world positions X(p(t)) + u), and the model's potential at the step's end time t is
//
//   E(u, P; t) = E_el(X(p(t)); X(p(t)) + u, E, nu) - (M(rho) (g - d2X/dt2(t)))^T u,
//
// two time-dependent terms (the integrator sets t = t_{n+1} before each step, forward and
// backward) plus the integrator's inertia and, with alpha > 0, Rayleigh mass damping
// D = alpha/2 u'^T M u'. With implicit Euler this is MovingRestDynamics's step exactly (the same
// minimization, c/(2h^2)|u' - u - h v/c|_M^2 up to a constant, c = 1 + alpha h). Parameters
// P = [E_e; nu_e; rho_e; alpha; beta] (per element, then the damping pair; beta stays 0: the
// stiffness-proportional part would use the bind pose's K). Fixed vertices: u = 0 (eliminated).
#include <memory>

#include "forward/core/model.hpp"
#include "forward/dynamics/mass_operator.hpp"
#include "forward/dynamics/time_dependent.hpp"
#include "forward/fem/elastic_term.hpp"
#include "forward/rig/rigged_body.hpp"

namespace tailor {

// E_el(X(p(t)); X(p(t)) + u, E, nu): the elastic energy of the mesh whose rest shape is the
// rigged shape at the time last set, evaluated at the displacement u from it. Every derivative
// (in u, in E and nu) is the elastic term's at x = X + u, so the term is exact wherever it is.
class MovingRestElasticTerm final : public EnergyTerm, public TimeDependent {
 public:
  // rig and trajectory must outlive the term; youngs_offset / poisson_offset as ElasticTerm.
  MovingRestElasticTerm(const Rig& rig, const PoseTrajectory& trajectory, Mesh mesh, MaterialKind material,
                        int youngs_offset, int poisson_offset);
  std::string name() const override { return "moving_rest_elastic"; }
  void evaluate(const Vector& u, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override { elastic_->hessian_pattern(pattern); }
  void add_param_gradient(const Vector& u, const Vector& p, Vector& gradient_p) const override;
  void add_mixed(const Vector& u, const Vector& p, Triplets& mixed) const override;
  void add_mixed_transpose_times(const Vector& u, const Vector& p, const Vector& w, Vector& gradient_p) const override;
  void set_time(double time) override;  // rebuilds the rest shape X(p(time)) (O(elements))
  const Vector& rest_shape() const { return rest_; }

 private:
  const Rig& rig_;
  const PoseTrajectory& trajectory_;
  Mesh mesh_;
  std::shared_ptr<const Material<3>> material_;
  int youngs_offset_, poisson_offset_;
  double time_;
  Vector rest_;
  std::unique_ptr<ElasticTerm<3>> elastic_;
};

// -(M(rho) (g - d2X/dt2(t)))^T u: gravity and the inertial load of the rig's motion at the time
// last set, linear in u; its density derivatives come from the mass operator.
class RigInertialLoadTerm final : public EnergyTerm, public TimeDependent {
 public:
  RigInertialLoadTerm(const Rig& rig, const PoseTrajectory& trajectory, std::shared_ptr<const MassOperator> mass,
                      const Eigen::Vector3d& gravity, bool inertial_forces);
  std::string name() const override { return "rig_inertial_load"; }
  void evaluate(const Vector& u, const Vector& p, const EnergyRequest& request) const override;
  bool hessian_is_constant() const override { return true; }  // zero
  void add_param_gradient(const Vector& u, const Vector& p, Vector& gradient_p) const override;
  void add_mixed(const Vector& u, const Vector& p, Triplets& mixed) const override;
  void set_time(double time) override;
  // g - d2X/dt2 at the time last set (3n, per unit mass).
  const Vector& acceleration() const { return acceleration_; }

 private:
  const Rig& rig_;
  const PoseTrajectory& trajectory_;
  std::shared_ptr<const MassOperator> mass_;
  Vector gravity_;
  bool inertial_;
  Vector acceleration_;
};

struct MovingRestModel {
  std::unique_ptr<Model> model;
  Vector parameters;  // P at the body's values (alpha = the options' Rayleigh mass coefficient, beta = 0)
  int youngs_offset = 0, poisson_offset = 0, density_offset = 0, alpha_offset = -1;
  MovingRestElasticTerm* elastic = nullptr;
  RigInertialLoadTerm* load = nullptr;
};

// The model of a rigged body along a trajectory (both must outlive it). Throws
// std::invalid_argument as MovingRestDynamics does for a body that does not fit the rig.
MovingRestModel moving_rest_model(const Rig& rig, const PoseTrajectory& trajectory, const RiggedBody& body,
                                  const MovingRestOptions& options);

}  // namespace tailor
