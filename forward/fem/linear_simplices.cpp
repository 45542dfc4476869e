#include "forward/fem/linear_simplices.hpp"

#include "forward/fem/nodal_kinematics.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <stdexcept>
#include <string>

namespace tailor {

template <int Dim>
LinearSimplices<Dim>::LinearSimplices(const Mesh& mesh, std::vector<int> covered, const std::string& owner)
    : elements(std::move(covered)) {
  if (mesh.dim() != Dim || mesh.elements.cols() != kNodes)
    throw std::invalid_argument(owner + "<" + std::to_string(Dim) + ">: the mesh has dimension " +
                                std::to_string(mesh.dim()));
  if (elements.empty()) {
    elements.resize(mesh.num_elements());
    for (int e = 0; e < mesh.num_elements(); ++e) elements[e] = e;
  }
  {
    std::vector<int> sorted = elements;
    std::sort(sorted.begin(), sorted.end());
    const auto twice = std::adjacent_find(sorted.begin(), sorted.end());
    if (twice != sorted.end())
      throw std::invalid_argument(owner + ": element " + std::to_string(*twice) + " is listed twice");
  }
  vertices.resize(elements.size());
  gradients.resize(elements.size());
  volumes.resize(elements.size());
  for (std::size_t k = 0; k < elements.size(); ++k) {
    const int e = elements[k];
    if (e < 0 || e >= mesh.num_elements())
      throw std::invalid_argument(owner + ": element index " + std::to_string(e) + " out of range");
    Mat Dm;
    for (int a = 0; a < Dim; ++a)
      Dm.col(a) =
          (mesh.rest_positions.row(mesh.elements(e, a + 1)) - mesh.rest_positions.row(mesh.elements(e, 0)))
              .transpose();
    const double det = Dm.determinant();
    if (!(det > 0.0))
      throw std::invalid_argument(owner + ": element " + std::to_string(e) +
                                  " is degenerate or inverted at rest (signed measure " +
                                  std::to_string(det) + ")");
    const Mat Dm_inv = Dm.inverse();
    ShapeGradients G;
    G.template bottomRows<Dim>() = Dm_inv;  // grad N_a = row a-1 of Dm^{-1}
    G.row(0) = -Dm_inv.colwise().sum();
    gradients[k] = G;
    volumes[k] = det / (Dim == 3 ? 6.0 : 2.0);
    for (int a = 0; a < kNodes; ++a) vertices[k][a] = mesh.elements(e, a);
  }
}

template <int Dim>
typename LinearSimplices<Dim>::Mat LinearSimplices<Dim>::field_gradient(const Vector& x, int k) const {
  return nodal_field_gradient<Dim, kNodes>(x, vertices[k], gradients[k]);
}

template <int Dim>
typename LinearSimplices<Dim>::Jacobian LinearSimplices<Dim>::deformation_jacobian(const ShapeGradients& G) {
  return nodal_deformation_jacobian<Dim, kNodes>(G);
}

template <int Dim>
void LinearSimplices<Dim>::append_hessian_pattern(HessianPattern& pattern) const {
  append_element_hessian_pattern<Dim, kNodes>(vertices, pattern);
}

template <int Dim>
LinearSimplices<Dim> LinearSimplices<Dim>::subset(const std::vector<int>& covered) const {
  LinearSimplices out;
  out.elements.reserve(covered.size());
  out.vertices.reserve(covered.size());
  out.gradients.reserve(covered.size());
  out.volumes.reserve(covered.size());
  for (int k : covered) {
    if (k < 0 || k >= size()) throw std::out_of_range("LinearSimplices::subset: no covered element " + std::to_string(k));
    out.elements.push_back(elements[static_cast<std::size_t>(k)]);
    out.vertices.push_back(vertices[static_cast<std::size_t>(k)]);
    out.gradients.push_back(gradients[static_cast<std::size_t>(k)]);
    out.volumes.push_back(volumes[static_cast<std::size_t>(k)]);
  }
  return out;
}

template struct LinearSimplices<2>;
template struct LinearSimplices<3>;

}  // namespace tailor
