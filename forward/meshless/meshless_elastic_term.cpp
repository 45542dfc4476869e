#include "forward/meshless/meshless_elastic_term.hpp"

#include <algorithm>
#include <stdexcept>

#include "forward/core/parallel_errors.hpp"

namespace tailor {

namespace {

// With vec(F) column-major, F_ij = sum_t x_{t,i} g_t[j], so dvec(F)_(i+3j) / dx_{t,i'} =
// delta_ii' g_t[j]. The products with B = dvec(F)/dx_local (9 x 3n) are written out over that
// structure: no dense 9 x 3n matrix, and no dynamic-size matrix product to compile.

// C_t = B_t^T T (3 x 9): C_t(i, c) = sum_j g_t[j] T(i + 3j, c).
Eigen::Matrix<double, 3, 9> left_contraction(const Eigen::Vector3d& g, const Eigen::Matrix<double, 9, 9>& T) {
  Eigen::Matrix<double, 3, 9> C;
  for (int c = 0; c < 9; ++c)
    for (int i = 0; i < 3; ++i) C(i, c) = g[0] * T(i, c) + g[1] * T(i + 3, c) + g[2] * T(i + 6, c);
  return C;
}

}  // namespace

template <int Dim>
MeshlessElasticTerm<Dim>::MeshlessElasticTerm(std::shared_ptr<const MeshlessQuadrature> quadrature,
                                              std::shared_ptr<const Material<Dim>> material, int youngs_offset,
                                              int poisson_offset)
    : quadrature_(std::move(quadrature)),
      material_(std::move(material)),
      youngs_offset_(youngs_offset),
      poisson_offset_(poisson_offset) {
  if (!material_) throw std::invalid_argument("MeshlessElasticTerm: no material given");
  if (!quadrature_ || quadrature_->num_points() == 0)
    throw std::invalid_argument("MeshlessElasticTerm: no quadrature points");
  const MeshlessQuadrature& Q = *quadrature_;
  for (int q = 0; q < Q.num_points(); ++q)
    for (int t = Q.begin[static_cast<std::size_t>(q)] + 1; t < Q.begin[static_cast<std::size_t>(q) + 1]; ++t)
      if (!(Q.nodes[static_cast<std::size_t>(t - 1)] < Q.nodes[static_cast<std::size_t>(t)]))
        throw std::invalid_argument("MeshlessElasticTerm: the nodes of quadrature point " + std::to_string(q) +
                                    " are not increasing");
  std::vector<std::vector<int>> adjacency(static_cast<std::size_t>(Q.num_nodes));
  for (int q = 0; q < Q.num_points(); ++q)
    for (int s = Q.begin[static_cast<std::size_t>(q)]; s < Q.begin[static_cast<std::size_t>(q) + 1]; ++s)
      for (int t = Q.begin[static_cast<std::size_t>(q)]; t < Q.begin[static_cast<std::size_t>(q) + 1]; ++t)
        adjacency[static_cast<std::size_t>(Q.nodes[static_cast<std::size_t>(s)])].push_back(
            Q.nodes[static_cast<std::size_t>(t)]);
  adjacency_begin_.push_back(0);
  for (auto& row : adjacency) {
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    adjacency_.insert(adjacency_.end(), row.begin(), row.end());
    adjacency_begin_.push_back(static_cast<int>(adjacency_.size()));
  }
  // Per adjacency entry (a, b): the position of (b, a); per node: its diagonal entry.
  diagonal_.resize(static_cast<std::size_t>(Q.num_nodes));
  transpose_.resize(adjacency_.size());
  std::vector<int> walk(adjacency_begin_.begin(), adjacency_begin_.end() - 1);
  for (int a = 0; a < Q.num_nodes; ++a)
    for (int s = adjacency_begin_[static_cast<std::size_t>(a)]; s < adjacency_begin_[static_cast<std::size_t>(a) + 1]; ++s) {
      const int b = adjacency_[static_cast<std::size_t>(s)];
      if (b == a) diagonal_[static_cast<std::size_t>(a)] = s;
      // Rows are visited in increasing a, so b's entries for a come in order.
      transpose_[static_cast<std::size_t>(s)] = walk[static_cast<std::size_t>(b)]++;
    }
  // Per node: the points covering it, increasing, with the entry of the node in each.
  node_point_begin_.assign(static_cast<std::size_t>(Q.num_nodes) + 1, 0);
  for (int node : Q.nodes) ++node_point_begin_[static_cast<std::size_t>(node) + 1];
  for (int a = 0; a < Q.num_nodes; ++a) node_point_begin_[static_cast<std::size_t>(a) + 1] += node_point_begin_[static_cast<std::size_t>(a)];
  node_point_.resize(Q.nodes.size());
  node_point_entry_.resize(Q.nodes.size());
  std::vector<int> fill(node_point_begin_.begin(), node_point_begin_.end() - 1);
  for (int q = 0; q < Q.num_points(); ++q)
    for (int t = Q.begin[static_cast<std::size_t>(q)]; t < Q.begin[static_cast<std::size_t>(q) + 1]; ++t) {
      const int k = fill[static_cast<std::size_t>(Q.nodes[static_cast<std::size_t>(t)])]++;
      node_point_[static_cast<std::size_t>(k)] = q;
      node_point_entry_[static_cast<std::size_t>(k)] = t;
    }
}

template <int Dim>
LameParameters MeshlessElasticTerm<Dim>::lame(const Vector& p, int q) const {
  return lame_from_young_poisson(quadrature_->interpolate(p, youngs_offset_, q),
                                 quadrature_->interpolate(p, poisson_offset_, q));
}

template <int Dim>
Eigen::Matrix2d MeshlessElasticTerm<Dim>::lame_chain(const Vector& p, int q) const {
  return lame_jacobian(quadrature_->interpolate(p, youngs_offset_, q), quadrature_->interpolate(p, poisson_offset_, q));
}

template <int Dim>
void MeshlessElasticTerm<Dim>::hessian_pattern(HessianPattern& pattern) const {
  pattern.reserve(pattern.size() + 9 * adjacency_.size());
  for (int a = 0; a + 1 < static_cast<int>(adjacency_begin_.size()); ++a)
    for (int s = adjacency_begin_[static_cast<std::size_t>(a)]; s < adjacency_begin_[static_cast<std::size_t>(a) + 1]; ++s)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) pattern.push_back({3 * a + i, 3 * adjacency_[static_cast<std::size_t>(s)] + j});
}

template <int Dim>
void MeshlessElasticTerm<Dim>::evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const {
  const MeshlessQuadrature& Q = *quadrature_;
  const bool want_gradient = request.gradient != nullptr, want_hessian = request.hessian_values != nullptr;
  const int num_points = Q.num_points();
  // 1. Per point (in parallel, each point writes its own record): w_q Psi, w_q P_q and T_q.
  std::vector<double> energy(static_cast<std::size_t>(num_points));
  std::vector<Eigen::Matrix3d> stress(want_gradient ? static_cast<std::size_t>(num_points) : 0);
  std::vector<Eigen::Matrix<double, 9, 9>> tangent(want_hessian ? static_cast<std::size_t>(num_points) : 0);
  FirstError errors;
#pragma omp parallel for schedule(static) if (num_points > 256)
  for (int q = 0; q < num_points; ++q) try {
    MaterialEvaluation<Dim> m;
    material_->evaluate(Q.deformation_gradient(x, q), lame(p, q), want_gradient, want_hessian, request.hessian_mode, m);
    const double w = Q.weights[static_cast<std::size_t>(q)];
    energy[static_cast<std::size_t>(q)] = w * m.energy_density;
    if (want_gradient) stress[static_cast<std::size_t>(q)] = w * m.stress;
    if (want_hessian) tangent[static_cast<std::size_t>(q)] = m.tangent;
  } catch (...) {
    errors.capture(q);
  }
  errors.rethrow();
  if (request.value) {
    double sum = 0.0;
    for (double e : energy) sum += e;
    *request.value += sum;
  }
  if (!want_gradient && !want_hessian) return;
  // 2. Per node a (in parallel, each node writes its own gradient entries and Hessian blocks),
  //    over the points covering it in increasing order: the same sums in the same order for
  //    every thread count. The tangent is symmetric, so block (b, a) = block (a, b)^T: the
  //    blocks b >= a are summed, the others copied.
  const int num_nodes = Q.num_nodes;
#pragma omp parallel for schedule(dynamic, 16) if (num_nodes > 64)
  for (int a = 0; a < num_nodes; ++a) {
    const int diagonal = diagonal_[static_cast<std::size_t>(a)];
    const int row_end = adjacency_begin_[static_cast<std::size_t>(a) + 1];
    if (want_hessian) std::fill(request.hessian_values + 9 * diagonal, request.hessian_values + 9 * row_end, 0.0);
    for (int k = node_point_begin_[static_cast<std::size_t>(a)]; k < node_point_begin_[static_cast<std::size_t>(a) + 1]; ++k) {
      const int q = node_point_[static_cast<std::size_t>(k)];
      const int first = Q.begin[static_cast<std::size_t>(q)], n = Q.size(q);
      const int s = node_point_entry_[static_cast<std::size_t>(k)] - first;  // a is the point's node s
      const Eigen::Vector3d& g_a = Q.gradients[static_cast<std::size_t>(first + s)];
      if (want_gradient) request.gradient->segment<3>(3 * a) += stress[static_cast<std::size_t>(q)] * g_a;
      if (!want_hessian) continue;
      // Block (a, b) += w B_a^T T B_b: (C B_b)(i, k) = sum_l C(i, k + 3l) g_b[l]. The point's nodes
      // increase, so their slots in a's adjacency row are found by one forward walk along it.
      const Eigen::Matrix<double, 3, 9> C = Q.weights[static_cast<std::size_t>(q)] * left_contraction(g_a, tangent[static_cast<std::size_t>(q)]);
      int position = diagonal;
      for (int t = s; t < n; ++t) {
        const Eigen::Vector3d& g = Q.gradients[static_cast<std::size_t>(first + t)];
        const int b = Q.nodes[static_cast<std::size_t>(first + t)];
        while (adjacency_[static_cast<std::size_t>(position)] < b) ++position;
        double* block = request.hessian_values + 9 * position;
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) block[3 * i + j] += C(i, j) * g[0] + C(i, j + 3) * g[1] + C(i, j + 6) * g[2];
      }
    }
    if (want_hessian)
      for (int position = diagonal + 1; position < row_end; ++position) {
        const double* block = request.hessian_values + 9 * position;
        double* mirror = request.hessian_values + 9 * transpose_[static_cast<std::size_t>(position)];
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) mirror[3 * j + i] = block[3 * i + j];
      }
  }
  }

template <int Dim>
void MeshlessElasticTerm<Dim>::add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const {
  const MeshlessQuadrature& Q = *quadrature_;
  for (int q = 0; q < Q.num_points(); ++q) {
    MaterialLameDerivatives<Dim> d;
    material_->lame_derivatives(Q.deformation_gradient(x, q), lame(p, q), d);
    // d E / d(E_q, nu_q), spread to the nodes by dE_q / dE_a = phi_a(X_q).
    const Eigen::RowVector2d g = Q.weights[static_cast<std::size_t>(q)] * d.energy_density.transpose() * lame_chain(p, q);
    for (int t = Q.begin[static_cast<std::size_t>(q)]; t < Q.begin[static_cast<std::size_t>(q) + 1]; ++t) {
      const int a = Q.nodes[static_cast<std::size_t>(t)];
      gradient_p[youngs_offset_ + a] += Q.values[static_cast<std::size_t>(t)] * g[0];
      gradient_p[poisson_offset_ + a] += Q.values[static_cast<std::size_t>(t)] * g[1];
    }
  }
}

template <int Dim>
void MeshlessElasticTerm<Dim>::add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const {
  const MeshlessQuadrature& Q = *quadrature_;
  for (int q = 0; q < Q.num_points(); ++q) {
    const int first = Q.begin[static_cast<std::size_t>(q)], n = Q.size(q);
    MaterialLameDerivatives<Dim> d;
    material_->lame_derivatives(Q.deformation_gradient(x, q), lame(p, q), d);
    const Eigen::Matrix<double, 9, 2> dP = d.stress * lame_chain(p, q);  // dvec(P)/d(E_q, nu_q)
    const double w = Q.weights[static_cast<std::size_t>(q)];
    for (int s = 0; s < n; ++s) {
      const Eigen::Vector3d& g = Q.gradients[static_cast<std::size_t>(first + s)];
      for (int i = 0; i < 3; ++i) {
        const int dof = 3 * Q.nodes[static_cast<std::size_t>(first + s)] + i;
        // (B^T dP)(3s + i, c) = sum_j g_s[j] dP(i + 3j, c).
        const double dE = w * (g[0] * dP(i, 0) + g[1] * dP(i + 3, 0) + g[2] * dP(i + 6, 0));
        const double dnu = w * (g[0] * dP(i, 1) + g[1] * dP(i + 3, 1) + g[2] * dP(i + 6, 1));
        for (int t = 0; t < n; ++t) {
          const int b = Q.nodes[static_cast<std::size_t>(first + t)];
          const double phi = Q.values[static_cast<std::size_t>(first + t)];
          mixed.emplace_back(dof, youngs_offset_ + b, phi * dE);
          mixed.emplace_back(dof, poisson_offset_ + b, phi * dnu);
        }
      }
    }
  }
}

template <int Dim>
void MeshlessElasticTerm<Dim>::add_mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w,
                                                         Vector& gradient_p) const {
  const MeshlessQuadrature& Q = *quadrature_;
  for (int q = 0; q < Q.num_points(); ++q) {
    MaterialLameDerivatives<Dim> d;
    material_->lame_derivatives(Q.deformation_gradient(x, q), lame(p, q), d);
    // w contracted with dvec(F_q)/dx: the field gradient of w at X_q.
    const Eigen::Matrix3d W = Q.deformation_gradient(w, q);
    const Eigen::Map<const Eigen::Matrix<double, 9, 1>> w_vec(W.data());
    const Eigen::RowVector2d g =
        Q.weights[static_cast<std::size_t>(q)] * (w_vec.transpose() * d.stress) * lame_chain(p, q);
    for (int t = Q.begin[static_cast<std::size_t>(q)]; t < Q.begin[static_cast<std::size_t>(q) + 1]; ++t) {
      const int a = Q.nodes[static_cast<std::size_t>(t)];
      gradient_p[youngs_offset_ + a] += Q.values[static_cast<std::size_t>(t)] * g[0];
      gradient_p[poisson_offset_ + a] += Q.values[static_cast<std::size_t>(t)] * g[1];
    }
  }
}

template class MeshlessElasticTerm<3>;

}  // namespace tailor
