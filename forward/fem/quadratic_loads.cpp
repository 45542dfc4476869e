#include "forward/fem/quadratic_loads.hpp"

#include <Eigen/Geometry>
#include <stdexcept>
#include <string>

#include "forward/fem/p2_shape_functions.hpp"
#include "forward/fem/quadratic_simplices.hpp"
#include "forward/fem/simplex_quadrature.hpp"

namespace tailor {
namespace {

// Calls visit(node, N_a * dA, n dA) ... for every quadrature point of every facet: `visit(f, N,
// area_normal)` with N the facet's P2 values and area_normal = (dX/dxi rotated, or the cross
// product of the two tangents) times the weight, whose length is the weighted area element.
template <int FacetDim, class Rule, class Visit>
void for_each_quadratic_facet_point(const QuadraticMesh& mesh, const Eigen::MatrixXi& facets, const Rule& rule,
                                    Visit visit) {
  constexpr int kFacetNodes = P2Shape<FacetDim>::kNodes;
  constexpr int kDim = FacetDim + 1;
  if (facets.rows() > 0 && facets.cols() != kFacetNodes)
    throw std::invalid_argument("quadratic facet loads: facets must have " + std::to_string(kFacetNodes) +
                                " nodes (quadratic_facets)");
  for (Eigen::Index f = 0; f < facets.rows(); ++f) {
    Eigen::Matrix<double, kFacetNodes, kDim> X;
    for (int a = 0; a < kFacetNodes; ++a) {
      const int node = facets(f, a);
      if (node < 0 || node >= mesh.num_nodes()) throw std::out_of_range("quadratic facet loads: node out of range");
      X.row(a) = mesh.rest_positions.row(node);
    }
    for (int q = 0; q < Rule::kPoints; ++q) {
      const auto& xi = rule.points[static_cast<std::size_t>(q)];
      const Eigen::Matrix<double, kDim, FacetDim> T = X.transpose() * P2Shape<FacetDim>::gradients(xi);  // tangents
      Eigen::Matrix<double, kDim, 1> normal;
      if constexpr (kDim == 2) {
        // Edge (a, b) with outward normal to the right of a -> b (boundary_facets' orientation).
        normal << T(1, 0), -T(0, 0);
      } else {
        normal = T.col(0).cross(T.col(1));
      }
      visit(f, P2Shape<FacetDim>::values(xi), rule.weights[static_cast<std::size_t>(q)] * normal);
    }
  }
}

// Adds sum over facet points of N_a * load(area_normal) to f.
template <class Load>
Vector quadratic_facet_forces(const QuadraticMesh& mesh, const Eigen::MatrixXi& facets, Load load) {
  const int dim = mesh.dim();
  Vector f = Vector::Zero(static_cast<Eigen::Index>(dim) * mesh.num_nodes());
  auto add = [&](Eigen::Index k, const auto& N, const auto& area_normal) {
    const Eigen::VectorXd force = load(Eigen::VectorXd(area_normal));
    for (int a = 0; a < N.size(); ++a) f.segment(dim * facets(k, a), dim) += N[a] * force;
  };
  if (dim == 2)
    for_each_quadratic_facet_point<1>(mesh, facets, segment_rule_degree5(), add);
  else
    for_each_quadratic_facet_point<2>(mesh, facets, triangle_rule_degree4(), add);
  return f;
}

}  // namespace

Vector quadratic_traction_forces(const QuadraticMesh& mesh, const Eigen::MatrixXi& facets,
                                 const Eigen::VectorXd& traction) {
  if (traction.size() != mesh.dim())
    throw std::invalid_argument("quadratic_traction_forces: traction must have one component per dimension");
  return quadratic_facet_forces(mesh, facets, [&](const Eigen::VectorXd& area_normal) -> Eigen::VectorXd {
    return area_normal.norm() * traction;
  });
}

Vector quadratic_pressure_forces(const QuadraticMesh& mesh, const Eigen::MatrixXi& facets, double pressure) {
  return quadratic_facet_forces(mesh, facets,
                                [&](const Eigen::VectorXd& area_normal) -> Eigen::VectorXd { return -pressure * area_normal; });
}

namespace {

template <int Dim>
Vector quadratic_gravity_forces_dim(const QuadraticMesh& mesh, const Eigen::VectorXd& density,
                                    const Eigen::VectorXd& gravity) {
  const QuadraticSimplices<Dim> elements(mesh, {}, "quadratic_gravity_forces");
  const auto& rule = [&]() -> const SimplexRule<Dim, Dim + 1>& {
    if constexpr (Dim == 3)
      return tetrahedron_rule_degree2();
    else
      return triangle_rule_degree2();
  }();
  Vector f = Vector::Zero(static_cast<Eigen::Index>(Dim) * mesh.num_nodes());
  for (int k = 0; k < elements.size(); ++k)
    for (int q = 0; q < Dim + 1; ++q) {
      const auto N = P2Shape<Dim>::values(rule.points[static_cast<std::size_t>(q)]);
      const double mass = density[k] * elements.weight(k, q);
      for (int a = 0; a < P2Shape<Dim>::kNodes; ++a)
        f.segment<Dim>(Dim * elements.vertices[static_cast<std::size_t>(k)][a]) += N[a] * mass * gravity;
    }
  return f;
}

}  // namespace

Vector quadratic_gravity_forces(const QuadraticMesh& mesh, const Eigen::VectorXd& density,
                                const Eigen::VectorXd& gravity) {
  if (gravity.size() != mesh.dim())
    throw std::invalid_argument("quadratic_gravity_forces: gravity must have one component per dimension");
  if (density.size() != mesh.num_elements())
    throw std::invalid_argument("quadratic_gravity_forces: one density per element expected");
  return mesh.dim() == 3 ? quadratic_gravity_forces_dim<3>(mesh, density, gravity)
                         : quadratic_gravity_forces_dim<2>(mesh, density, gravity);
}

}  // namespace tailor
