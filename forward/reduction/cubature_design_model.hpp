#pragma once
// The reduced design model of any material by cubature (An, Kim, James, "Optimizing cubature
// for efficient integration of subspace deformations", SIGGRAPH Asia 2008): a few elements C
// with non-negative weights omega_e stand in for the sum over the mesh,
//
//   W(q; w) = sum_{e in C} omega_e (1 + y_e^T w) V_e Psi(F_e(q); E0_e),
//
// y_e the element's row of the material modes (E_e = E0_e (1 + y_e^T w), and Psi is linear in
// E at fixed Poisson's ratio). The force, stiffness and mixed derivative are exact derivatives
// of this W; each evaluation costs O(|C| r^2), independent of the mesh. With C = every element
// and omega = 1 it is the projected full model (ProjectedReducedModel) of design w.
// The rule is fitted by fit_cubature (forward/reduction/cubature.hpp).
#include <vector>

#include "forward/reduction/reduced_design_model.hpp"
#include "forward/reduction/subspace_elements.hpp"

namespace tailor {

class CubatureDesignModel final : public ReducedDesignModel {
 public:
  // elements: the rule's elements (E0 in their Lame parameters); weights: omega, one per element,
  // >= 0; material_modes: y, one row per mesh element (indexed by elements.mesh_element), m
  // columns. Throws std::invalid_argument for inconsistent sizes or a negative weight.
  CubatureDesignModel(SubspaceElements elements, Vector weights, const Matrix& material_modes);
  std::string name() const override { return "cubature"; }
  int size() const override { return elements_.reduced_size(); }
  int design_size() const override { return static_cast<int>(design_rows_.cols()); }
  int num_elements() const { return elements_.size(); }
  const Vector& weights() const { return weights_; }
  void evaluate(const Vector& q, const Vector& w, double* energy, Vector* force, Matrix* stiffness) const override;
  Matrix force_design_derivative(const Vector& q) const override;
  Vector force_design_derivative_transpose(const Vector& q, const Vector& lambda) const override;

 private:
  SubspaceElements elements_;
  Vector weights_;
  Matrix design_rows_;  // y_e of the rule's elements, |C| x m
};

}  // namespace tailor
