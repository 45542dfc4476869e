#include "forward/rig/moving_rest_model.hpp"

#include <stdexcept>

#include "forward/core/elimination.hpp"
#include "forward/dynamics/setup.hpp"
#include "forward/rig/rigged_body.hpp"

namespace tailor {

MovingRestElasticTerm::MovingRestElasticTerm(const Rig& rig, const PoseTrajectory& trajectory, Mesh mesh,
                                             MaterialKind material, int youngs_offset, int poisson_offset)
    : rig_(rig),
      trajectory_(trajectory),
      mesh_(std::move(mesh)),
      material_(make_material<3>(material)),
      youngs_offset_(youngs_offset),
      poisson_offset_(poisson_offset),
      time_(0.0) {
  if (mesh_.num_vertices() != rig_.num_vertices())
    throw std::invalid_argument("moving rest elastic term: the mesh and the rig have different vertex counts");
  rest_ = rig_.rest_shape(trajectory_(time_).p);
  elastic_ = std::make_unique<ElasticTerm<3>>(posed_mesh(mesh_, rest_), material_, youngs_offset_, poisson_offset_);
}

void MovingRestElasticTerm::set_time(double time) {
  if (time == time_) return;
  time_ = time;
  rest_ = rig_.rest_shape(trajectory_(time).p);
  elastic_ = std::make_unique<ElasticTerm<3>>(posed_mesh(mesh_, rest_), material_, youngs_offset_, poisson_offset_);
}

void MovingRestElasticTerm::evaluate(const Vector& u, const Vector& p, const EnergyRequest& request) const {
  elastic_->evaluate(rest_ + u, p, request);
}

void MovingRestElasticTerm::add_param_gradient(const Vector& u, const Vector& p, Vector& gradient_p) const {
  elastic_->add_param_gradient(rest_ + u, p, gradient_p);
}

void MovingRestElasticTerm::add_mixed(const Vector& u, const Vector& p, Triplets& mixed) const {
  elastic_->add_mixed(rest_ + u, p, mixed);
}

void MovingRestElasticTerm::add_mixed_transpose_times(const Vector& u, const Vector& p, const Vector& w,
                                                      Vector& gradient_p) const {
  elastic_->add_mixed_transpose_times(rest_ + u, p, w, gradient_p);
}

RigInertialLoadTerm::RigInertialLoadTerm(const Rig& rig, const PoseTrajectory& trajectory,
                                         std::shared_ptr<const MassOperator> mass, const Eigen::Vector3d& gravity,
                                         bool inertial_forces)
    : rig_(rig), trajectory_(trajectory), mass_(std::move(mass)), inertial_(inertial_forces) {
  gravity_.resize(3 * rig_.num_vertices());
  for (int v = 0; v < rig_.num_vertices(); ++v) gravity_.segment<3>(3 * v) = gravity;
  set_time(0.0);
}

void RigInertialLoadTerm::set_time(double time) {
  acceleration_ = gravity_;
  if (inertial_) acceleration_ -= rig_.rest_shape_acceleration(trajectory_(time));
}

void RigInertialLoadTerm::evaluate(const Vector& u, const Vector& p, const EnergyRequest& request) const {
  if (!request.value && !request.gradient) return;
  Vector force = Vector::Zero(u.size());
  mass_->add_times(p, acceleration_, force);
  if (request.value) *request.value -= force.dot(u);
  if (request.gradient) *request.gradient -= force;
}

void RigInertialLoadTerm::add_param_gradient(const Vector& u, const Vector& p, Vector& gradient_p) const {
  (void)p;
  mass_->add_density_gradient(u, acceleration_, gradient_p, -1.0);
}

void RigInertialLoadTerm::add_mixed(const Vector& u, const Vector& p, Triplets& mixed) const {
  (void)u, (void)p;
  mass_->add_density_jacobian(acceleration_, mixed, -1.0);
}

MovingRestModel moving_rest_model(const Rig& rig, const PoseTrajectory& trajectory, const RiggedBody& body,
                                  const MovingRestOptions& options) {
  const int ne = body.mesh.num_elements(), n = 3 * body.mesh.num_vertices();
  if (body.mesh.num_vertices() != rig.num_vertices())
    throw std::invalid_argument("moving rest model: the mesh and the rig have different vertex counts");
  if (body.youngs_modulus.size() != ne || body.poisson_ratio.size() != ne || body.density.size() != ne)
    throw std::invalid_argument("moving rest model: Young's modulus, Poisson's ratio and density are per element");
  MovingRestModel out;
  out.model = std::make_unique<Model>(n);
  Model& model = *out.model;
  out.youngs_offset = model.parameter_layout().add("youngs_modulus", ne);
  out.poisson_offset = model.parameter_layout().add("poisson_ratio", ne);
  out.elastic = &model.add(std::make_unique<MovingRestElasticTerm>(rig, trajectory, body.mesh, body.material,
                                                                   out.youngs_offset, out.poisson_offset));
  DynamicsSetup setup;
  setup.lumping = MassLumping::consistent;
  setup.rayleigh = options.rayleigh_mass > 0.0;
  const DynamicTerms terms = add_dynamics_terms(model, body.mesh, setup);
  out.density_offset = terms.density_offset;
  out.alpha_offset = terms.alpha_offset;
  auto mass = std::make_shared<const MassOperator>(body.mesh, MassLumping::consistent, terms.density_offset);
  out.load = &model.add(std::make_unique<RigInertialLoadTerm>(rig, trajectory, mass, body.gravity, options.inertial_forces));
  std::vector<int> fixed_dofs;
  for (int v : body.fixed_vertices) {
    if (v < 0 || v >= body.mesh.num_vertices()) throw std::invalid_argument("moving rest model: fixed vertex out of range");
    for (int c = 0; c < 3; ++c) fixed_dofs.push_back(3 * v + c);
  }
  model.set_elimination(Elimination::dirichlet(fixed_dofs, Vector::Zero(n)));
  out.parameters = Vector::Zero(model.parameter_layout().size());
  out.parameters.segment(out.youngs_offset, ne) = body.youngs_modulus;
  out.parameters.segment(out.poisson_offset, ne) = body.poisson_ratio;
  out.parameters.segment(out.density_offset, ne) = body.density;
  if (setup.rayleigh) out.parameters[out.alpha_offset] = options.rayleigh_mass;
  return out;
}

}  // namespace tailor
