#pragma once
// The kinematics every simplicial element shares, whatever its node count (linear simplices:
// Dim + 1 nodes, one point per element; quadratic ones: 6 or 10 nodes, evaluated at each
// quadrature point): the gradient of a nodal field, d vec(F) / d x_local and the Hessian
// pattern of the element DOFs. Local DOFs are node-major: local DOF Dim * a + i is component i
// of local node a.
#include <Eigen/Core>
#include <array>
#include <functional>
#include <vector>

#include "forward/core/types.hpp"

namespace tailor {

// Gradient of the nodal field x (positions or any per-node vector field, interleaved) over an
// element with global nodes `nodes` and rest shape gradients G (row a: grad N_a):
// sum_a x_a grad(N_a)^T.
template <int Dim, int Nodes>
Eigen::Matrix<double, Dim, Dim> nodal_field_gradient(const Vector& x, const Eigen::Matrix<int, Nodes, 1>& nodes,
                                                     const Eigen::Matrix<double, Nodes, Dim>& G) {
  Eigen::Matrix<double, Dim, Dim> F = Eigen::Matrix<double, Dim, Dim>::Zero();
  for (int a = 0; a < Nodes; ++a) F.noalias() += x.template segment<Dim>(Dim * nodes[a]) * G.row(a);
  return F;
}

// d vec(F) / d x_local: entry (i + Dim*j, Dim*a + k) = delta_ik G(a, j).
template <int Dim, int Nodes>
Eigen::Matrix<double, Dim * Dim, Dim * Nodes> nodal_deformation_jacobian(const Eigen::Matrix<double, Nodes, Dim>& G) {
  Eigen::Matrix<double, Dim * Dim, Dim * Nodes> B = Eigen::Matrix<double, Dim * Dim, Dim * Nodes>::Zero();
  for (int a = 0; a < Nodes; ++a)
    for (int j = 0; j < Dim; ++j)
      for (int i = 0; i < Dim; ++i) B(i + Dim * j, Dim * a + i) = G(a, j);
  return B;
}

// The (Dim Nodes)^2 slots of every element, row-major, appended to pattern.
template <int Dim, int Nodes, class NodeLists>
void append_element_hessian_pattern(const NodeLists& nodes, HessianPattern& pattern) {
  constexpr int kLocal = Dim * Nodes;
  pattern.reserve(pattern.size() + nodes.size() * kLocal * kLocal);
  for (const auto& element : nodes)
    for (int r = 0; r < kLocal; ++r)
      for (int c = 0; c < kLocal; ++c) pattern.push_back({Dim * element[r / Dim] + r % Dim, Dim * element[c / Dim] + c % Dim});
}

// The elements of `simplices` (LinearSimplices or QuadraticSimplices) whose element DOFs `keep`
// accepts, in order: the subset an elastic term's EnergyTerm::share_by_elements keeps.
template <class Simplices>
std::vector<int> elements_kept(const Simplices& simplices, const std::function<bool(const int* dofs, int count)>& keep) {
  std::vector<int> kept;
  std::array<int, Simplices::kLocal> dofs;
  for (int k = 0; k < simplices.size(); ++k) {
    for (int r = 0; r < Simplices::kLocal; ++r) dofs[static_cast<std::size_t>(r)] = simplices.dof(k, r);
    if (keep(dofs.data(), Simplices::kLocal)) kept.push_back(k);
  }
  return kept;
}

}  // namespace tailor
