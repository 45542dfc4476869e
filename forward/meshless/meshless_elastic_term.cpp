#include "forward/meshless/meshless_elastic_term.hpp"

#include <algorithm>
#include <stdexcept>

namespace tailor {

namespace {

// B = dvec(F)/dx_local (9 x 3n, vec column-major): F_ij = sum_t x_{t,i} g_t[j].
Eigen::MatrixXd deformation_jacobian(const MeshlessQuadrature& quadrature, int q) {
  const int first = quadrature.begin[static_cast<std::size_t>(q)];
  const int n = quadrature.size(q);
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(9, 3 * n);
  for (int t = 0; t < n; ++t) {
    const Eigen::Vector3d& g = quadrature.gradients[static_cast<std::size_t>(first + t)];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) B(i + 3 * j, 3 * t + i) = g[j];
  }
  return B;
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
}

template <int Dim>
int MeshlessElasticTerm<Dim>::slot(int a, int b) const {
  const auto first = adjacency_.begin() + adjacency_begin_[static_cast<std::size_t>(a)];
  const auto last = adjacency_.begin() + adjacency_begin_[static_cast<std::size_t>(a) + 1];
  const auto it = std::lower_bound(first, last, b);
  return 9 * static_cast<int>(it - adjacency_.begin());
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
  if (want_hessian) std::fill(request.hessian_values, request.hessian_values + 9 * adjacency_.size(), 0.0);
  double energy = 0.0;
  for (int q = 0; q < Q.num_points(); ++q) {
    const int first = Q.begin[static_cast<std::size_t>(q)], n = Q.size(q);
    MaterialEvaluation<Dim> m;
    material_->evaluate(Q.deformation_gradient(x, q), lame(p, q), want_gradient, want_hessian, request.hessian_mode, m);
    const double w = Q.weights[static_cast<std::size_t>(q)];
    energy += w * m.energy_density;
    if (want_gradient)
      for (int t = 0; t < n; ++t)
        request.gradient->segment<3>(3 * Q.nodes[static_cast<std::size_t>(first + t)]) +=
            w * m.stress * Q.gradients[static_cast<std::size_t>(first + t)];
    if (want_hessian) {
      const Eigen::MatrixXd B = deformation_jacobian(Q, q);
      const Eigen::MatrixXd H = w * (B.transpose() * (m.tangent * B));
      for (int s = 0; s < n; ++s) {
        const int a = Q.nodes[static_cast<std::size_t>(first + s)];
        for (int t = 0; t < n; ++t) {
          double* block = request.hessian_values + slot(a, Q.nodes[static_cast<std::size_t>(first + t)]);
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) block[3 * i + j] += H(3 * s + i, 3 * t + j);
        }
      }
    }
  }
  if (request.value) *request.value += energy;
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
    const Eigen::MatrixXd local = Q.weights[static_cast<std::size_t>(q)] * (deformation_jacobian(Q, q).transpose() * dP);
    for (int s = 0; s < n; ++s)
      for (int i = 0; i < 3; ++i) {
        const int dof = 3 * Q.nodes[static_cast<std::size_t>(first + s)] + i;
        for (int t = 0; t < n; ++t) {
          const int b = Q.nodes[static_cast<std::size_t>(first + t)];
          const double phi = Q.values[static_cast<std::size_t>(first + t)];
          mixed.emplace_back(dof, youngs_offset_ + b, phi * local(3 * s + i, 0));
          mixed.emplace_back(dof, poisson_offset_ + b, phi * local(3 * s + i, 1));
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
