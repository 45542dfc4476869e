#include "forward/dynamics/inertia_term.hpp"

#include <stdexcept>

namespace tailor {

InertiaTerm::InertiaTerm(std::shared_ptr<const MassOperator> mass) : mass_(std::move(mass)) {
  if (!mass_) throw std::invalid_argument("InertiaTerm: no mass operator");
  predictor_ = Vector::Zero(mass_->num_dofs());
}

void InertiaTerm::set_step(double coefficient, Vector predictor, Vector carried_force) {
  if (!(coefficient >= 0.0)) throw std::invalid_argument("InertiaTerm: the inertia coefficient must be >= 0");
  if (predictor.size() != mass_->num_dofs())
    throw std::invalid_argument("InertiaTerm: predictor has the wrong size");
  if (carried_force.size() != 0 && carried_force.size() != mass_->num_dofs())
    throw std::invalid_argument("InertiaTerm: carried force has the wrong size");
  coefficient_ = coefficient;
  predictor_ = std::move(predictor);
  carried_force_ = std::move(carried_force);
}

void InertiaTerm::evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const {
  if (request.value || request.gradient) {
    const Vector d = x - predictor_;
    Vector Md = Vector::Zero(x.size());
    mass_->add_times(p, d, Md, coefficient_);
    if (request.value) {
      *request.value += 0.5 * d.dot(Md);
      if (carried_force_.size()) *request.value -= carried_force_.dot(d);
    }
    if (request.gradient) {
      *request.gradient += Md;
      if (carried_force_.size()) *request.gradient -= carried_force_;
    }
  }
  if (request.hessian_values) mass_->hessian_values(p, coefficient_, request.hessian_values);
}

void InertiaTerm::add_hessian_times(const Vector& x, const Vector& p, const Vector& w, Vector& out,
                                    HessianMode mode) const {
  (void)x, (void)mode;  // c M is constant and positive semidefinite: exact and projected coincide
  if (coefficient_ != 0.0) mass_->add_times(p, w, out, coefficient_);
}

void InertiaTerm::add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const {
  (void)p;
  const Vector d = x - predictor_;
  mass_->add_density_gradient(d, d, gradient_p, 0.5 * coefficient_);
}

void InertiaTerm::add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const {
  (void)p;
  mass_->add_density_jacobian(x - predictor_, mixed, coefficient_);
}

void InertiaTerm::add_mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w,
                                            Vector& gradient_p) const {
  (void)p;
  mass_->add_density_gradient(w, x - predictor_, gradient_p, coefficient_);
}

}  // namespace tailor
