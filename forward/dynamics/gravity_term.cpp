#include "forward/dynamics/gravity_term.hpp"

#include <stdexcept>

namespace tailor {

GravityTerm::GravityTerm(const Mesh& mesh, Eigen::VectorXd gravity, int density_offset)
    : gravity_(std::move(gravity)), density_offset_(density_offset), elements_(mesh.elements) {
  if (gravity_.size() != mesh.dim())
    throw std::invalid_argument("GravityTerm: gravity must have one component per dimension");
  shares_ = element_volumes(mesh) / (mesh.dim() + 1);
  rest_.resize(mesh.dim() * mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v)
    rest_.segment(mesh.dim() * v, mesh.dim()) = mesh.rest_positions.row(v).transpose();
}

double GravityTerm::element_work(const Vector& w, int e) const {
  const int dim = static_cast<int>(gravity_.size());
  double s = 0.0;
  for (int a = 0; a < elements_.cols(); ++a) s += gravity_.dot(w.segment(dim * elements_(e, a), dim));
  return shares_[e] * s;
}

void GravityTerm::evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const {
  const int dim = static_cast<int>(gravity_.size());
  const Vector u = request.value ? Vector(x - rest_) : Vector();
  for (int e = 0; e < elements_.rows(); ++e) {
    const double rho = p[density_offset_ + e];
    if (request.value) *request.value -= rho * element_work(u, e);
    if (request.gradient)
      for (int a = 0; a < elements_.cols(); ++a)
        request.gradient->segment(dim * elements_(e, a), dim) -= rho * shares_[e] * gravity_;
  }
}

void GravityTerm::add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const {
  (void)p;
  const Vector u = x - rest_;
  for (int e = 0; e < elements_.rows(); ++e) gradient_p[density_offset_ + e] -= element_work(u, e);
}

void GravityTerm::add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const {
  (void)x, (void)p;
  const int dim = static_cast<int>(gravity_.size());
  for (int e = 0; e < elements_.rows(); ++e)
    for (int a = 0; a < elements_.cols(); ++a)
      for (int i = 0; i < dim; ++i)
        if (gravity_[i] != 0.0)
          mixed.emplace_back(dim * elements_(e, a) + i, density_offset_ + e, -shares_[e] * gravity_[i]);
}

void GravityTerm::add_mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w,
                                            Vector& gradient_p) const {
  (void)x, (void)p;
  for (int e = 0; e < elements_.rows(); ++e) gradient_p[density_offset_ + e] -= element_work(w, e);
}

}  // namespace tailor
