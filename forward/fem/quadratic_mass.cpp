#include "forward/fem/quadratic_mass.hpp"

#include <Eigen/LU>
#include <stdexcept>
#include <string>

#include "forward/fem/p2_shape_functions.hpp"
#include "forward/fem/simplex_quadrature.hpp"

namespace tailor {
namespace {

template <int Dim, class Rule>
SparseMatrix quadratic_mass_matrix_dim(const QuadraticMesh& mesh, const Eigen::VectorXd& density, const Rule& rule) {
  constexpr int kNodes = P2Shape<Dim>::kNodes;
  Triplets triplets;
  triplets.reserve(static_cast<std::size_t>(mesh.num_elements()) * kNodes * kNodes * Dim);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    Eigen::Matrix<double, kNodes, Dim> X;
    for (int a = 0; a < kNodes; ++a) X.row(a) = mesh.rest_positions.row(mesh.elements(e, a));
    Eigen::Matrix<double, kNodes, kNodes> local = Eigen::Matrix<double, kNodes, kNodes>::Zero();
    for (int q = 0; q < Rule::kPoints; ++q) {
      const auto& xi = rule.points[static_cast<std::size_t>(q)];
      const double det = (X.transpose() * P2Shape<Dim>::gradients(xi)).determinant();
      if (!(det > 0.0))
        throw std::invalid_argument("quadratic_mass_matrix: element " + std::to_string(e) +
                                    " is degenerate or inverted at rest");
      const typename P2Shape<Dim>::Values N = P2Shape<Dim>::values(xi);
      local.noalias() += (density[e] * rule.weights[static_cast<std::size_t>(q)] * det) * N * N.transpose();
    }
    for (int a = 0; a < kNodes; ++a)
      for (int b = 0; b < kNodes; ++b)
        for (int i = 0; i < Dim; ++i)
          triplets.emplace_back(Dim * mesh.elements(e, a) + i, Dim * mesh.elements(e, b) + i, local(a, b));
  }
  const int n = Dim * mesh.num_nodes();
  SparseMatrix M(n, n);
  M.setFromTriplets(triplets.begin(), triplets.end());
  return M;
}

}  // namespace

SparseMatrix quadratic_mass_matrix(const QuadraticMesh& mesh, const Eigen::VectorXd& density) {
  if (density.size() != mesh.num_elements())
    throw std::invalid_argument("quadratic_mass_matrix: one density per element expected");
  if (mesh.dim() == 3) return quadratic_mass_matrix_dim<3>(mesh, density, tetrahedron_rule_degree4());
  return quadratic_mass_matrix_dim<2>(mesh, density, triangle_rule_degree4());
}

}  // namespace tailor
