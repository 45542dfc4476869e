#include "forward/dynamics/mass_operator.hpp"

#include <stdexcept>

namespace tailor {

MassOperator::MassOperator(const Mesh& mesh, MassLumping lumping, int density_offset)
    : dim_(mesh.dim()),
      nodes_(mesh.dim() + 1),
      num_dofs_(mesh.dim() * mesh.num_vertices()),
      density_offset_(density_offset),
      lumping_(lumping),
      elements_(mesh.elements),
      volumes_(element_volumes(mesh)) {
  if (density_offset < 0) throw std::invalid_argument("MassOperator: negative density offset");
  if (elements_.cols() != nodes_) throw std::invalid_argument("MassOperator: elements must be simplices");
}

MassOperator::MassOperator(Vector diagonal)
    : dim_(1),
      nodes_(1),
      num_dofs_(static_cast<int>(diagonal.size())),
      density_offset_(0),
      lumping_(MassLumping::lumped),
      fixed_diagonal_(std::move(diagonal)) {
  if (fixed_diagonal_.size() == 0) throw std::invalid_argument("MassOperator: empty diagonal mass");
  if (!fixed_diagonal_.allFinite() || fixed_diagonal_.minCoeff() < 0.0)
    throw std::invalid_argument("MassOperator: diagonal masses must be finite and non-negative");
}

double MassOperator::coefficient(int a, int b) const {
  // consistent: (1 + delta_ab) / ((d + 1)(d + 2)); lumped: its row sum 1 / (d + 1) on the diagonal.
  if (lumping_ == MassLumping::lumped) return a == b ? 1.0 / nodes_ : 0.0;
  return (a == b ? 2.0 : 1.0) / (nodes_ * (nodes_ + 1));
}

void MassOperator::add_times(const Vector& p, const Vector& w, Vector& out, double scale) const {
  if (is_fixed_diagonal()) {
    out += scale * fixed_diagonal_.cwiseProduct(w);
    return;
  }
  for (int e = 0; e < num_elements(); ++e) {
    const double m = scale * p[density_offset_ + e] * volumes_[e];
    for (int a = 0; a < nodes_; ++a)
      for (int b = 0; b < nodes_; ++b) {
        const double c = coefficient(a, b);
        if (c == 0.0) continue;
        out.segment(dim_ * elements_(e, a), dim_) += (m * c) * w.segment(dim_ * elements_(e, b), dim_);
      }
  }
}

void MassOperator::add_density_gradient(const Vector& a_vec, const Vector& b_vec, Vector& gradient_p,
                                        double scale) const {
  for (int e = 0; e < num_elements(); ++e) {
    double s = 0.0;
    for (int a = 0; a < nodes_; ++a)
      for (int b = 0; b < nodes_; ++b) {
        const double c = coefficient(a, b);
        if (c != 0.0)
          s += c *
               a_vec.segment(dim_ * elements_(e, a), dim_).dot(b_vec.segment(dim_ * elements_(e, b), dim_));
      }
    gradient_p[density_offset_ + e] += scale * volumes_[e] * s;
  }
}

void MassOperator::add_density_jacobian(const Vector& w, Triplets& triplets, double scale) const {
  for (int e = 0; e < num_elements(); ++e)
    for (int a = 0; a < nodes_; ++a)
      for (int i = 0; i < dim_; ++i) {
        double s = 0.0;
        for (int b = 0; b < nodes_; ++b) s += coefficient(a, b) * w[dim_ * elements_(e, b) + i];
        if (s != 0.0)
          triplets.emplace_back(dim_ * elements_(e, a) + i, density_offset_ + e, scale * volumes_[e] * s);
      }
}

std::size_t MassOperator::pattern_size() const {
  if (is_fixed_diagonal()) return static_cast<std::size_t>(num_dofs_);
  const std::size_t per_element = lumping_ == MassLumping::lumped ? nodes_ * dim_ : nodes_ * nodes_ * dim_;
  return per_element * static_cast<std::size_t>(num_elements());
}

void MassOperator::hessian_pattern(HessianPattern& pattern) const {
  pattern.reserve(pattern.size() + pattern_size());
  if (is_fixed_diagonal()) {
    for (int i = 0; i < num_dofs_; ++i) pattern.push_back({i, i});
    return;
  }
  for (int e = 0; e < num_elements(); ++e)
    for (int a = 0; a < nodes_; ++a)
      for (int b = 0; b < nodes_; ++b) {
        if (lumping_ == MassLumping::lumped && a != b) continue;
        for (int i = 0; i < dim_; ++i)
          pattern.push_back({dim_ * elements_(e, a) + i, dim_ * elements_(e, b) + i});
      }
}

void MassOperator::hessian_values(const Vector& p, double scale, double* values) const {
  std::size_t k = 0;
  if (is_fixed_diagonal()) {
    for (int i = 0; i < num_dofs_; ++i) values[k++] = scale * fixed_diagonal_[i];
    return;
  }
  for (int e = 0; e < num_elements(); ++e) {
    const double m = scale * p[density_offset_ + e] * volumes_[e];
    for (int a = 0; a < nodes_; ++a)
      for (int b = 0; b < nodes_; ++b) {
        if (lumping_ == MassLumping::lumped && a != b) continue;
        const double v = m * coefficient(a, b);
        for (int i = 0; i < dim_; ++i) values[k++] = v;
      }
  }
}

SparseMatrix MassOperator::matrix(const Vector& p) const {
  HessianPattern pattern;
  hessian_pattern(pattern);
  std::vector<double> values(pattern.size());
  hessian_values(p, 1.0, values.data());
  Triplets triplets;
  triplets.reserve(pattern.size());
  for (std::size_t k = 0; k < pattern.size(); ++k)
    triplets.emplace_back(pattern[k].row, pattern[k].col, values[k]);
  SparseMatrix M(num_dofs_, num_dofs_);
  M.setFromTriplets(triplets.begin(), triplets.end());
  return M;
}

}  // namespace tailor
