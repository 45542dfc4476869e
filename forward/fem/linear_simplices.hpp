#pragma once
// Rest geometry of linear simplicial elements (tets in 3D, triangles in 2D) shared by the
// hyperelastic energy terms: per covered element its vertices, the rest shape-function gradients
// and the rest volume (area in 2D, per unit thickness). F_e(x) = sum_a x_a grad(N_a)^T.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "forward/core/types.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor {

template <int Dim>
struct LinearSimplices {
  static constexpr int kNodes = Dim + 1;
  static constexpr int kLocal = Dim * kNodes;                 // element DOFs
  using ShapeGradients = Eigen::Matrix<double, kNodes, Dim>;  // row a: grad N_a at rest
  using Mat = Eigen::Matrix<double, Dim, Dim>;
  using Jacobian = Eigen::Matrix<double, Dim * Dim, kLocal>;  // d vec(F) / d x_local

  // `elements`: the mesh elements covered (all when empty). Throws std::invalid_argument, naming
  // `owner`, when the mesh dimension is not Dim, an index is out of range or repeated, or an
  // element is degenerate or inverted at rest.
  LinearSimplices(const Mesh& mesh, std::vector<int> elements, const std::string& owner);
  LinearSimplices() = default;  // covers nothing (see subset)

  // The covered elements k in `covered` (indices into elements), in that order.
  LinearSimplices subset(const std::vector<int>& covered) const;

  int size() const { return static_cast<int>(elements.size()); }
  // Gradient of the vertex field x (positions, or any per-vertex vector field) on covered element k.
  Mat field_gradient(const Vector& x, int k) const;
  // d vec(F) / d x_local: entry (i + Dim*j, Dim*a + k) = delta_ik G(a, j).
  static Jacobian deformation_jacobian(const ShapeGradients& G);
  // Global DOF of local DOF r of covered element k.
  int dof(int k, int r) const { return Dim * vertices[k][r / Dim] + r % Dim; }
  // The kLocal x kLocal slots of every covered element, row-major, appended to pattern.
  void append_hessian_pattern(HessianPattern& pattern) const;

  std::vector<int> elements;
  std::vector<Eigen::Matrix<int, kNodes, 1>> vertices;
  std::vector<ShapeGradients> gradients;
  std::vector<double> volumes;
};

extern template struct LinearSimplices<2>;
extern template struct LinearSimplices<3>;

}  // namespace tailor
