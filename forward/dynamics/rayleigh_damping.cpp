#include "forward/dynamics/rayleigh_damping.hpp"

#include <algorithm>
#include <stdexcept>

#include "forward/fem/elastic_term.hpp"

namespace tailor {

RayleighDamping::RayleighDamping(const Mesh& mesh, std::shared_ptr<const MassOperator> mass, int alpha_offset,
                                 int beta_offset, int youngs_offset, int poisson_offset)
    : mass_(std::move(mass)),
      alpha_offset_(alpha_offset),
      beta_offset_(beta_offset),
      youngs_offset_(youngs_offset),
      poisson_offset_(poisson_offset),
      num_elements_(mesh.num_elements()) {
  if (!mass_) throw std::invalid_argument("RayleighDamping: no mass operator");
  if (mesh.dim() == 3)
    stiffness_ = std::make_unique<ElasticTerm<3>>(mesh, make_material<3>(MaterialKind::linear), youngs_offset,
                                                  poisson_offset);
  else
    stiffness_ = std::make_unique<ElasticTerm<2>>(mesh, make_material<2>(MaterialKind::linear), youngs_offset,
                                                  poisson_offset);
  rest_.resize(mesh.dim() * mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v)
    rest_.segment(mesh.dim() * v, mesh.dim()) = mesh.rest_positions.row(v).transpose();
  mass_slots_ = mass_->pattern_size();
  HessianPattern k_pattern;
  stiffness_->hessian_pattern(k_pattern);
  stiffness_slots_ = k_pattern.size();
  // K's compressed pattern, and the entry of each slot (found in its column's sorted rows).
  Triplets ones;
  ones.reserve(k_pattern.size());
  for (const HessianEntry& e : k_pattern) ones.emplace_back(e.row, e.col, 1.0);
  stiffness_pattern_.resize(rest_.size(), rest_.size());
  stiffness_pattern_.setFromTriplets(ones.begin(), ones.end());
  stiffness_pattern_.makeCompressed();
  const int* outer = stiffness_pattern_.outerIndexPtr();
  const int* inner = stiffness_pattern_.innerIndexPtr();
  slot_entry_.resize(k_pattern.size());
  for (std::size_t k = 0; k < k_pattern.size(); ++k) {
    const int* first = inner + outer[k_pattern[k].col];
    const int* last = inner + outer[k_pattern[k].col + 1];
    slot_entry_[k] = static_cast<int>(std::lower_bound(first, last, k_pattern[k].row) - inner);
  }
  std::fill_n(stiffness_pattern_.valuePtr(), stiffness_pattern_.nonZeros(), 0.0);
}

void RayleighDamping::evaluate_dissipation(const Vector& v, const Vector& p,
                                           const EnergyRequest& request) const {
  const double alpha = p[alpha_offset_], beta = p[beta_offset_];
  if (request.value || request.gradient) {
    Vector Mv = Vector::Zero(v.size());
    mass_->add_times(p, v, Mv, alpha);
    const Vector Kv = *cached_stiffness(p) * v;
    if (request.value) *request.value += 0.5 * v.dot(Mv) + 0.5 * beta * v.dot(Kv);
    if (request.gradient) {
      *request.gradient += Mv;
      *request.gradient += beta * Kv;
    }
  }
  if (request.hessian_values) {
    mass_->hessian_values(p, alpha, request.hessian_values);
    double* k_values = request.hessian_values + mass_slots_;
    EnergyRequest k_request;
    k_request.hessian_values = k_values;
    stiffness_->evaluate(rest_ + v, p, k_request);
    for (std::size_t k = 0; k < stiffness_slots_; ++k) k_values[k] *= beta;
  }
}

void RayleighDamping::dissipation_pattern(HessianPattern& pattern) const {
  mass_->hessian_pattern(pattern);
  stiffness_->hessian_pattern(pattern);
}

void RayleighDamping::add_dissipation_param_gradient(const Vector& v, const Vector& p,
                                                     Vector& gradient_p) const {
  const double alpha = p[alpha_offset_], beta = p[beta_offset_];
  const Vector X_plus_v = rest_ + v;
  Vector Mv = Vector::Zero(v.size());
  mass_->add_times(p, v, Mv);
  gradient_p[alpha_offset_] += 0.5 * v.dot(Mv);
  gradient_p[beta_offset_] += stiffness_->value(X_plus_v, p);
  mass_->add_density_gradient(v, v, gradient_p, 0.5 * alpha);
  Vector gk = Vector::Zero(p.size());
  stiffness_->add_param_gradient(X_plus_v, p, gk);
  gradient_p += beta * gk;
}

bool RayleighDamping::add_dissipation_hessian_times(const Vector& v, const Vector& p, const Vector& w,
                                                    Vector& out) const {
  (void)v;
  mass_->add_times(p, w, out, p[alpha_offset_]);
  out += p[beta_offset_] * (*cached_stiffness(p) * w);
  return true;
}

void RayleighDamping::add_dissipation_mixed_transpose_times(const Vector& v, const Vector& p, const Vector& w,
                                                            Vector& gradient_p) const {
  const double alpha = p[alpha_offset_], beta = p[beta_offset_];
  const Vector X_plus_v = rest_ + v;
  Vector Mv = Vector::Zero(v.size());
  mass_->add_times(p, v, Mv);
  gradient_p[alpha_offset_] += w.dot(Mv);
  gradient_p[beta_offset_] += w.dot(*cached_stiffness(p) * v);  // K v, the kept K (as the gradient)
  mass_->add_density_gradient(w, v, gradient_p, alpha);
  Vector gk = Vector::Zero(p.size());
  stiffness_->add_mixed_transpose_times(X_plus_v, p, w, gk);
  gradient_p += beta * gk;
}

void RayleighDamping::add_dissipation_mixed(const Vector& v, const Vector& p, Triplets& mixed) const {
  const double alpha = p[alpha_offset_], beta = p[beta_offset_];
  const Vector X_plus_v = rest_ + v;
  Vector Mv = Vector::Zero(v.size()), Kv = Vector::Zero(v.size());
  mass_->add_times(p, v, Mv);
  stiffness_->add_gradient(X_plus_v, p, Kv);
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (Mv[i] != 0.0) mixed.emplace_back(static_cast<int>(i), alpha_offset_, Mv[i]);
    if (Kv[i] != 0.0) mixed.emplace_back(static_cast<int>(i), beta_offset_, Kv[i]);
  }
  mass_->add_density_jacobian(v, mixed, alpha);
  Triplets k_mixed;
  stiffness_->add_mixed(X_plus_v, p, k_mixed);
  for (const auto& t : k_mixed) mixed.emplace_back(t.row(), t.col(), beta * t.value());
}

std::shared_ptr<const SparseMatrix> RayleighDamping::cached_stiffness(const Vector& p) const {
  Vector key(2 * num_elements_);
  key << p.segment(youngs_offset_, num_elements_), p.segment(poisson_offset_, num_elements_);
  const std::lock_guard<std::mutex> lock(cache_mutex_);
  if (!cache_ || key != cache_key_) {
    std::vector<double> values(stiffness_slots_, 0.0);
    EnergyRequest request;
    request.hessian_values = values.data();
    stiffness_->evaluate(rest_, p, request);
    auto K = std::make_shared<SparseMatrix>(stiffness_pattern_);
    double* entries = K->valuePtr();
    for (std::size_t k = 0; k < stiffness_slots_; ++k) entries[slot_entry_[k]] += values[k];
    cache_ = std::move(K);
    cache_key_ = std::move(key);
  }
  return cache_;
}

SparseMatrix RayleighDamping::rest_stiffness(const Vector& p) const { return *cached_stiffness(p); }

}  // namespace tailor
