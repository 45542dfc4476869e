#include "forward/dynamics/mass_operator.hpp"

#include <stdexcept>
#include <vector>

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
  if (nodes_ > 4) throw std::invalid_argument("MassOperator: simplices of dimension at most 3");
  // Vertex -> (element, local node) incidences, by element then local node: add_times sums a
  // vertex's contributions in the order of an element-by-element scatter.
  const int num_vertices = mesh.num_vertices();
  vertex_begin_.assign(static_cast<std::size_t>(num_vertices) + 1, 0);
  for (int e = 0; e < num_elements(); ++e)
    for (int a = 0; a < nodes_; ++a) {
      const int v = elements_(e, a);
      if (v < 0 || v >= num_vertices)
        throw std::invalid_argument("MassOperator: an element names a missing vertex");
      ++vertex_begin_[static_cast<std::size_t>(v) + 1];
    }
  for (int v = 0; v < num_vertices; ++v) vertex_begin_[v + 1] += vertex_begin_[v];
  incidences_.resize(static_cast<std::size_t>(vertex_begin_.back()));
  std::vector<int> fill(vertex_begin_.begin(), vertex_begin_.end() - 1);
  for (int e = 0; e < num_elements(); ++e)
    for (int a = 0; a < nodes_; ++a) incidences_[fill[elements_(e, a)]++] = e * nodes_ + a;
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
  // Row by row (vertex by vertex) instead of scattering element by element, so that vertices
  // run in parallel; each vertex adds its elements' terms in element order, the same sums in
  // the same order as the scatter (so the same bits for every thread count).
  constexpr int kMaxNodes = 4;
  double c[kMaxNodes][kMaxNodes];
  for (int a = 0; a < nodes_; ++a)
    for (int b = 0; b < nodes_; ++b) c[a][b] = coefficient(a, b);
  const int num_vertices = static_cast<int>(vertex_begin_.size()) - 1;
  const double* wv = w.data();
  double* ov = out.data();
  const int* elements = elements_.data();  // column-major: node b of element e at b * n + e
  const auto n = static_cast<std::ptrdiff_t>(elements_.rows());
#pragma omp parallel for schedule(static) if (num_vertices > 2048)
  for (int v = 0; v < num_vertices; ++v) {
    double* o = ov + static_cast<std::ptrdiff_t>(dim_) * v;
    for (int t = vertex_begin_[v]; t < vertex_begin_[v + 1]; ++t) {
      const int e = incidences_[t] / nodes_, a = incidences_[t] % nodes_;
      const double m = scale * p[density_offset_ + e] * volumes_[e];
      for (int b = 0; b < nodes_; ++b) {
        if (c[a][b] == 0.0) continue;
        const double mc = m * c[a][b];
        const double* wb = wv + static_cast<std::ptrdiff_t>(dim_) * elements[b * n + e];
        for (int i = 0; i < dim_; ++i) o[i] += mc * wb[i];
      }
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
