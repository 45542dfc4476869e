#include "forward/reduction/overlapping_domains.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "forward/core/symmetric_eigen.hpp"
#include "forward/reduction/domain_decomposition.hpp"
#include "forward/reduction/domain_partition.hpp"
#include "forward/reduction/free_space.hpp"
#include "forward/solve/sparse_cholesky.hpp"

namespace tailor {

std::vector<int> grown_region(const Mesh& mesh, const Eigen::VectorXi& element_domain, int domain, int layers) {
  std::vector<char> in(static_cast<std::size_t>(mesh.num_vertices()), 0);
  for (int e = 0; e < mesh.num_elements(); ++e)
    if (element_domain[e] == domain)
      for (int a = 0; a < mesh.elements.cols(); ++a) in[static_cast<std::size_t>(mesh.elements(e, a))] = 1;
  for (int layer = 0; layer < layers; ++layer) {
    std::vector<char> next = in;
    for (int e = 0; e < mesh.num_elements(); ++e) {
      bool touches = false;
      for (int a = 0; a < mesh.elements.cols(); ++a) touches = touches || in[static_cast<std::size_t>(mesh.elements(e, a))];
      if (touches)
        for (int a = 0; a < mesh.elements.cols(); ++a) next[static_cast<std::size_t>(mesh.elements(e, a))] = 1;
    }
    in.swap(next);
  }
  std::vector<int> out;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (in[static_cast<std::size_t>(v)]) out.push_back(v);
  return out;
}

OverlappingDomains overlapping_domains(const Model& model, const Mesh& mesh, const Vector& x, const Vector& p,
                                       const SparseMatrix& mass, const Eigen::VectorXi& element_domain,
                                       const OverlappingDomainOptions& options) {
  const auto begin = std::chrono::steady_clock::now();
  const int n = model.num_dofs(), dim = mesh.dim();
  if (n != dim * mesh.num_vertices() || x.size() != n || mass.rows() != n || mass.cols() != n)
    throw std::invalid_argument("overlapping_domains: model, mesh, state and mass sizes differ");
  if (element_domain.size() != mesh.num_elements() || element_domain.size() == 0 || element_domain.minCoeff() < 0)
    throw std::invalid_argument("overlapping_domains: need one domain index >= 0 per element");
  if (options.overlap_layers < 0 || options.block_size < 1 || options.max_iterations < 1 || !(options.tolerance > 0.0))
    throw std::invalid_argument("overlapping_domains: overlap_layers >= 0, block_size >= 1, max_iterations >= 1, "
                                "tolerance > 0");
  const std::vector<int> dof_to_free = free_index_of_dofs(model.elimination());
  const SparseMatrix& S = model.elimination().basis();
  const SparseMatrix K = free_stiffness(model, x, p), M = free_mass(model, mass);
  const int domains = domain_count(element_domain);

  OverlappingDomains out;
  out.weights = Matrix::Zero(mesh.num_vertices(), domains);
  out.principal_values.resize(domains);
  for (int d = 0; d < domains; ++d) {
    const std::vector<int> core = grown_region(mesh, element_domain, d, 0);
    const std::vector<int> region = grown_region(mesh, element_domain, d, options.overlap_layers);
    std::vector<char> in_core(static_cast<std::size_t>(mesh.num_vertices()), 0);
    for (int v : core) in_core[static_cast<std::size_t>(v)] = 1;
    std::vector<int> R, s;  // free unknowns of the region; positions of the core ones within R
    for (int v : region)
      for (int k = 0; k < dim; ++k) {
        const int f = dof_to_free[static_cast<std::size_t>(dim * v + k)];
        if (f < 0) continue;
        if (in_core[static_cast<std::size_t>(v)]) s.push_back(static_cast<int>(R.size()));
        R.push_back(f);
      }
    const int nr = static_cast<int>(R.size()), ns = static_cast<int>(s.size());
    if (ns == 0) throw std::runtime_error("overlapping_domains: domain " + std::to_string(d) + " has no free DOF");
    SparseMatrix upper = SparseMatrix(sparse_block(K, R, R).triangularView<Eigen::Upper>());
    upper.makeCompressed();
    SparseCholesky factor;
    const FactorizationResult f = factor.factorize(upper);
    if (!f.success || !f.positive_definite)
      throw std::runtime_error("overlapping_domains: the stiffness of region " + std::to_string(d) +
                               " is not positive definite: " + f.message);
    const SparseMatrix mrr = sparse_block(M, R, R);
    const auto displacement = [&](const Matrix& forces) {  // K_RR^{-1} E_s forces
      Matrix rhs = Matrix::Zero(nr, forces.cols());
      for (int i = 0; i < ns; ++i) rhs.row(s[static_cast<std::size_t>(i)]) = forces.row(i);
      return Matrix(factor.solve_columns(rhs));
    };
    const auto apply = [&](const Matrix& forces) {  // S^T M S forces
      const Matrix back = factor.solve_columns(Matrix(mrr * displacement(forces)));
      Matrix out_s(ns, forces.cols());
      for (int i = 0; i < ns; ++i) out_s.row(i) = back.row(s[static_cast<std::size_t>(i)]);
      return out_s;
    };
    // Subspace iteration with Rayleigh-Ritz; a deterministic start (smooth plus alternating).
    const int b = std::min(options.block_size, ns);
    Matrix X(ns, b);
    for (int i = 0; i < ns; ++i)
      for (int j = 0; j < b; ++j) X(i, j) = std::cos(0.37 * (i + 1) * (j + 1)) + (j == 0 ? 1.0 : 0.0);
    X = orthonormal_columns(X, b);
    Vector top;
    double mu = 0.0;
    int it = 0;
    for (; it < options.max_iterations; ++it) {
      const Matrix Z = apply(X);
      const Matrix projected = X.transpose() * Z;
      Vector ritz_values;
      Matrix ritz_vectors;
      symmetric_eigen<Eigen::Dynamic>(projected, ritz_values, ritz_vectors);  // ascending
      const Vector v = ritz_vectors.col(b - 1);
      mu = ritz_values[b - 1];
      top = X * v;
      const double residual = (Z * v - mu * top).norm();
      X = orthonormal_columns(Z, b);
      if (residual <= options.tolerance * std::abs(mu)) break;
    }
    if (it == options.max_iterations)
      throw std::runtime_error("overlapping_domains: the principal direction of domain " + std::to_string(d) +
                               " did not converge in " + std::to_string(it) + " iterations");
    top.normalize();
    // Deterministic sign: the largest entry positive.
    Eigen::Index largest = 0;
    top.cwiseAbs().maxCoeff(&largest);
    if (top[largest] < 0) top = -top;
    const Vector u_r = displacement(top);
    Vector force_y = Vector::Zero(K.rows()), u_y = Vector::Zero(K.rows());
    for (int i = 0; i < ns; ++i) force_y[R[static_cast<std::size_t>(s[static_cast<std::size_t>(i)])]] = top[i];
    for (int i = 0; i < nr; ++i) u_y[R[static_cast<std::size_t>(i)]] = u_r[i];
    out.principal_forces.push_back(S * force_y);
    out.principal_displacements.push_back(S * u_y);
    out.principal_values[d] = mu;
    out.region_vertices.push_back(region);
    out.iterations.push_back(it + 1);
    const Vector& u = out.principal_displacements.back();
    for (int v = 0; v < mesh.num_vertices(); ++v) out.weights(v, d) = u.segment(dim * v, dim).norm();
    const double peak = out.weights.col(d).maxCoeff();
    if (peak > 0.0) out.weights.col(d) /= peak;
  }
  // Partition of unity; vertices no displacement reaches go to the domains of their elements.
  Matrix touching = Matrix::Zero(mesh.num_vertices(), domains);
  for (int e = 0; e < mesh.num_elements(); ++e)
    for (int a = 0; a < mesh.elements.cols(); ++a) touching(mesh.elements(e, a), element_domain[e]) = 1.0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const double sum = out.weights.row(v).sum();
    if (sum > 0.0)
      out.weights.row(v) /= sum;
    else if (touching.row(v).sum() > 0.0)
      out.weights.row(v) = touching.row(v) / touching.row(v).sum();
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  return out;
}

Matrix blended_basis(const Matrix& weights, const Matrix& local, int dim) {
  if (local.rows() != dim * weights.rows())
    throw std::invalid_argument("blended_basis: " + std::to_string(local.rows()) + " rows for " +
                                std::to_string(weights.rows()) + " vertices in dimension " + std::to_string(dim));
  const Eigen::Index c = local.cols(), domains = weights.cols();
  Matrix out(local.rows(), domains * c);
  for (Eigen::Index d = 0; d < domains; ++d)
    for (Eigen::Index v = 0; v < weights.rows(); ++v)
      out.block(dim * v, d * c, dim, c) = weights(v, d) * local.middleRows(dim * v, dim);
  return out;
}

}  // namespace tailor
