#pragma once
// Rest geometry of quadratic simplicial elements (6-node triangles in 2D, 10-node tets in 3D;
// forward/mesh/quadratic_mesh.hpp) for the quadratic energy terms: per covered element its
// nodes, and per quadrature point the rest shape-function gradients and the weight
// w_q |det J_q| (volume, area per unit thickness in 2D). The elements are isoparametric:
// J_q = sum_a X_a (dN_a/dxi)^T at the point, so edge nodes moved off their midpoints (a curved
// boundary) are integrated as curved elements. F_q(x) = sum_a x_a grad(N_a)(xi_q)^T.
//
// Quadrature: the degree-2 rules (forward/fem/simplex_quadrature.hpp; 3 points on triangles, 4
// on tets). On straight-sided elements grad N is linear, so the P2 stiffness of linear
// elasticity (a quadratic integrand) is integrated exactly, as are the energy of a linear
// material under any quadratic displacement and a constant body force; it is also the lowest
// degree that keeps the element stiffness free of spurious zero-energy modes (Zienkiewicz &
// Taylor, Vol. 1, section 9.10). Nonlinear materials use the same rule: their integrand is no
// polynomial, the rule's error is O(h^3) in the energy like the interpolation's, and every
// derivative is the exact derivative of the integrated energy (Hughes 2000, section 3.8).
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "forward/core/types.hpp"
#include "forward/mesh/quadratic_mesh.hpp"

namespace tailor {

template <int Dim>
struct QuadraticSimplices {
  static constexpr int kNodes = (Dim + 1) * (Dim + 2) / 2;    // 6 or 10
  static constexpr int kLocal = Dim * kNodes;                 // element DOFs
  static constexpr int kPoints = Dim + 1;                     // quadrature points (degree 2)
  using ShapeGradients = Eigen::Matrix<double, kNodes, Dim>;  // row a: grad N_a at rest
  using Mat = Eigen::Matrix<double, Dim, Dim>;
  using Jacobian = Eigen::Matrix<double, Dim * Dim, kLocal>;  // d vec(F_q) / d x_local

  // `elements`: the mesh elements covered (all when empty). Throws std::invalid_argument, naming
  // `owner`, when the mesh dimension is not Dim, an index is out of range or repeated, or an
  // element is degenerate or inverted at rest at one of its quadrature points.
  QuadraticSimplices(const QuadraticMesh& mesh, std::vector<int> elements, const std::string& owner);
  QuadraticSimplices() = default;  // covers nothing (see subset)

  // The covered elements k in `covered` (indices into elements), in that order.
  QuadraticSimplices subset(const std::vector<int>& covered) const;

  int size() const { return static_cast<int>(elements.size()); }
  // Gradient of the nodal field x at quadrature point q of covered element k.
  Mat field_gradient(const Vector& x, int k, int q) const;
  const ShapeGradients& shape_gradients(int k, int q) const {
    return gradients[static_cast<std::size_t>(kPoints * k + q)];
  }
  double weight(int k, int q) const { return weights[static_cast<std::size_t>(kPoints * k + q)]; }
  // The rest volume of covered element k (the sum of its weights).
  double volume(int k) const;
  static Jacobian deformation_jacobian(const ShapeGradients& G);
  // Global DOF of local DOF r of covered element k.
  int dof(int k, int r) const { return Dim * vertices[static_cast<std::size_t>(k)][r / Dim] + r % Dim; }
  void append_hessian_pattern(HessianPattern& pattern) const;

  std::vector<int> elements;
  std::vector<Eigen::Matrix<int, kNodes, 1>> vertices;  // the element's nodes (named like LinearSimplices')
  std::vector<ShapeGradients> gradients;                // kPoints per element, point-major
  std::vector<double> weights;                          // w_q |det J_q|, kPoints per element
};

extern template struct QuadraticSimplices<2>;
extern template struct QuadraticSimplices<3>;

}  // namespace tailor
