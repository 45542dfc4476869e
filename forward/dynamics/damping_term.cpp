#include "forward/dynamics/damping_term.hpp"

#include <stdexcept>

namespace tailor {

void DampingTerm::set_velocity_map(double velocity_scale, Vector base) {
  if (!(velocity_scale > 0.0)) throw std::invalid_argument("DampingTerm: the velocity scale must be > 0");
  kappa_ = velocity_scale;
  base_ = std::move(base);
}

Vector DampingTerm::velocity(const Vector& x) const {
  if (base_.size() == 0) return x / kappa_;
  if (base_.size() != x.size())
    throw std::invalid_argument("DampingTerm: the velocity base has the wrong size");
  return (x - base_) / kappa_;
}

std::size_t DampingTerm::pattern_size() const {
  if (!pattern_known_) {
    HessianPattern pattern;
    dissipation_pattern(pattern);
    pattern_size_ = pattern.size();
    pattern_known_ = true;
  }
  return pattern_size_;
}

void DampingTerm::evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const {
  const Vector v = velocity(x);
  double dissipation = 0.0;
  EnergyRequest inner = request;
  inner.value = request.value ? &dissipation : nullptr;
  evaluate_dissipation(v, p, inner);
  // kappa D(v(x)): value kappa D, gradient dD/dv, Hessian d2D/dv2 / kappa.
  if (request.value) *request.value += kappa_ * dissipation;
  if (request.hessian_values) {
    const std::size_t n = pattern_size();
    for (std::size_t k = 0; k < n; ++k) request.hessian_values[k] /= kappa_;
  }
}

void DampingTerm::add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const {
  Vector g = Vector::Zero(gradient_p.size());
  add_dissipation_param_gradient(velocity(x), p, g);
  gradient_p += kappa_ * g;
}

void DampingTerm::add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const {
  add_dissipation_mixed(velocity(x), p, mixed);
}

void DampingTerm::add_mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w,
                                            Vector& gradient_p) const {
  add_dissipation_mixed_transpose_times(velocity(x), p, w, gradient_p);
}

void DampingTerm::add_low_rank_hessian(const Vector& x, const Vector& p, LowRankHessian& update,
                                       HessianMode mode) const {
  (void)mode;  // dissipation potentials are convex in v: exact and projected coincide
  LowRankHessian inner;
  add_dissipation_low_rank_hessian(velocity(x), p, inner);
  update.append(inner.factors, inner.core, 1.0 / kappa_);
}

void DampingTerm::add_hessian_times(const Vector& x, const Vector& p, const Vector& w, Vector& out,
                                    HessianMode mode) const {
  Vector on_pattern = Vector::Zero(out.size());
  if (!add_dissipation_hessian_times(velocity(x), p, w, on_pattern)) {
    EnergyTerm::add_hessian_times(x, p, w, out, mode);
    return;
  }
  out += on_pattern / kappa_;
  LowRankHessian low_rank;
  add_low_rank_hessian(x, p, low_rank, mode);
  low_rank.add_times(w, out);
}

void DampingTerm::add_dissipation_mixed(const Vector& v, const Vector& p, Triplets& mixed) const {
  // Row i of (d2D/dvdp)^T e_i, for every DOF: only for small problems and tests.
  Vector unit = Vector::Zero(v.size());
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    unit[i] = 1.0;
    Vector row = Vector::Zero(p.size());
    add_dissipation_mixed_transpose_times(v, p, unit, row);
    for (Eigen::Index j = 0; j < p.size(); ++j)
      if (row[j] != 0.0) mixed.emplace_back(static_cast<int>(i), static_cast<int>(j), row[j]);
    unit[i] = 0.0;
  }
}

}  // namespace tailor
