#include "forward/fem/quadratic_simplices.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <stdexcept>
#include <string>

#include "forward/fem/nodal_kinematics.hpp"
#include "forward/fem/p2_shape_functions.hpp"
#include "forward/fem/simplex_quadrature.hpp"

namespace tailor {
namespace {

template <int Dim>
const SimplexRule<Dim, Dim + 1>& quadratic_element_rule() {
  if constexpr (Dim == 3)
    return tetrahedron_rule_degree2();
  else
    return triangle_rule_degree2();
}

}  // namespace

template <int Dim>
QuadraticSimplices<Dim>::QuadraticSimplices(const QuadraticMesh& mesh, std::vector<int> covered,
                                            const std::string& owner)
    : elements(std::move(covered)) {
  if (mesh.dim() != Dim || mesh.elements.cols() != kNodes)
    throw std::invalid_argument(owner + "<" + std::to_string(Dim) + ">: the quadratic mesh has dimension " +
                                std::to_string(mesh.dim()));
  if (elements.empty()) {
    elements.resize(static_cast<std::size_t>(mesh.num_elements()));
    for (int e = 0; e < mesh.num_elements(); ++e) elements[static_cast<std::size_t>(e)] = e;
  }
  {
    std::vector<int> sorted = elements;
    std::sort(sorted.begin(), sorted.end());
    const auto twice = std::adjacent_find(sorted.begin(), sorted.end());
    if (twice != sorted.end())
      throw std::invalid_argument(owner + ": element " + std::to_string(*twice) + " is listed twice");
  }
  const auto& rule = quadratic_element_rule<Dim>();
  // The reference shape gradients at the points are the same for every element.
  std::array<typename P2Shape<Dim>::Gradients, kPoints> reference;
  for (int q = 0; q < kPoints; ++q) reference[static_cast<std::size_t>(q)] = P2Shape<Dim>::gradients(rule.points[static_cast<std::size_t>(q)]);
  vertices.resize(elements.size());
  gradients.resize(elements.size() * kPoints);
  weights.resize(elements.size() * kPoints);
  for (std::size_t k = 0; k < elements.size(); ++k) {
    const int e = elements[k];
    if (e < 0 || e >= mesh.num_elements())
      throw std::invalid_argument(owner + ": element index " + std::to_string(e) + " out of range");
    Eigen::Matrix<double, kNodes, Dim> X;
    for (int a = 0; a < kNodes; ++a) {
      vertices[k][a] = mesh.elements(e, a);
      X.row(a) = mesh.rest_positions.row(mesh.elements(e, a));
    }
    for (int q = 0; q < kPoints; ++q) {
      const auto& dN = reference[static_cast<std::size_t>(q)];
      const Mat J = X.transpose() * dN;  // dX/dxi
      const double det = J.determinant();
      if (!(det > 0.0))
        throw std::invalid_argument(owner + ": element " + std::to_string(e) +
                                    " is degenerate or inverted at rest (Jacobian determinant " +
                                    std::to_string(det) + " at quadrature point " + std::to_string(q) + ")");
      // grad N_a = J^{-T} dN_a/dxi, i.e. rows: dN J^{-1}.
      gradients[kPoints * k + static_cast<std::size_t>(q)] = dN * J.inverse();
      weights[kPoints * k + static_cast<std::size_t>(q)] = rule.weights[static_cast<std::size_t>(q)] * det;
    }
  }
}

template <int Dim>
typename QuadraticSimplices<Dim>::Mat QuadraticSimplices<Dim>::field_gradient(const Vector& x, int k, int q) const {
  return nodal_field_gradient<Dim, kNodes>(x, vertices[static_cast<std::size_t>(k)], shape_gradients(k, q));
}

template <int Dim>
double QuadraticSimplices<Dim>::volume(int k) const {
  double v = 0.0;
  for (int q = 0; q < kPoints; ++q) v += weight(k, q);
  return v;
}

template <int Dim>
typename QuadraticSimplices<Dim>::Jacobian QuadraticSimplices<Dim>::deformation_jacobian(const ShapeGradients& G) {
  return nodal_deformation_jacobian<Dim, kNodes>(G);
}

template <int Dim>
void QuadraticSimplices<Dim>::append_hessian_pattern(HessianPattern& pattern) const {
  append_element_hessian_pattern<Dim, kNodes>(vertices, pattern);
}

template <int Dim>
QuadraticSimplices<Dim> QuadraticSimplices<Dim>::subset(const std::vector<int>& covered) const {
  QuadraticSimplices out;
  for (int k : covered) {
    if (k < 0 || k >= size())
      throw std::out_of_range("QuadraticSimplices::subset: no covered element " + std::to_string(k));
    const auto ks = static_cast<std::size_t>(k);
    out.elements.push_back(elements[ks]);
    out.vertices.push_back(vertices[ks]);
    for (int q = 0; q < kPoints; ++q) {
      out.gradients.push_back(gradients[kPoints * ks + static_cast<std::size_t>(q)]);
      out.weights.push_back(weights[kPoints * ks + static_cast<std::size_t>(q)]);
    }
  }
  return out;
}

template struct QuadraticSimplices<2>;
template struct QuadraticSimplices<3>;

}  // namespace tailor
