#pragma once
// Hyperelastic energy of a meshless (MLS / element-free Galerkin) solid on its node DOFs
// (docs/meshless.md, "The energy"):
//   E(x, p) = sum_q w_q Psi(F_q; lambda_q, mu_q),  F_q = sum_a x_a grad phi_a(X_q)^T,
// x interleaved (x[3a + k]: component k of node a's coefficient; x_a = X_a is the rest state,
// which MLS reproduces exactly since the basis is at least linear). q runs over the points of a
// MeshlessQuadrature: each is like an element whose nodes are the nodes covering it.
//
// Parameters: per node, Young's modulus E_a = p[youngs_offset + a] and Poisson's ratio
// nu_a = p[poisson_offset + a], interpolated to the points by the shape functions,
// E_q = sum_a phi_a(X_q) E_a (and nu_q alike): a constant field is reproduced exactly and the
// map p -> (E_q, nu_q) is linear, so dE/dp_a = sum_q phi_a(X_q) dE/dE_q. A region's modulus
// is a parameterization of these (all its nodes share one value).
//
// Derivatives are exact: gradient sum_q w_q P_q grad phi_a, Hessian sum_q w_q B_q^T T_q B_q
// (B_q = dvec(F_q)/dx over the point's nodes, T_q the material's tangent, projected per point
// in HessianMode::projected), parameter gradient and mixed derivatives through the material's
// Lame derivatives. Every registered material works. A point's covering nodes must increase
// (as MlsShapeFunctions gives them; std::invalid_argument otherwise). The Hessian pattern has one 3 x 3 block per
// pair of nodes that share a quadrature point. The evaluation runs in parallel, deterministically
// (the same sums in the same order for every thread count): the material per point, then the
// gradient and Hessian blocks per node over the points covering it.
#include <memory>
#include <vector>

#include "forward/core/energy_term.hpp"
#include "forward/fem/material.hpp"
#include "forward/meshless/meshless_quadrature.hpp"

namespace tailor {

template <int Dim>
class MeshlessElasticTerm final : public EnergyTerm {
  static_assert(Dim == 3, "the meshless solid is three-dimensional");

 public:
  // std::invalid_argument without a material or with an empty quadrature.
  MeshlessElasticTerm(std::shared_ptr<const MeshlessQuadrature> quadrature, std::shared_ptr<const Material<Dim>> material,
                      int youngs_offset, int poisson_offset);

  std::string name() const override { return "meshless_elastic(" + material_->name() + ")"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;
  bool hessian_is_constant() const override { return material_->tangent_is_constant(); }
  void add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const override;
  void add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const override;
  void add_mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w, Vector& gradient_p) const override;

  const MeshlessQuadrature& quadrature() const { return *quadrature_; }
  const Material<Dim>& material() const { return *material_; }
  // Lame parameters at point q from the nodal E and nu in p.
  LameParameters lame(const Vector& p, int q) const;

 private:
  Eigen::Matrix2d lame_chain(const Vector& p, int q) const;  // d(lambda, mu)/d(E_q, nu_q)
  std::shared_ptr<const MeshlessQuadrature> quadrature_;
  std::shared_ptr<const Material<Dim>> material_;
  int youngs_offset_, poisson_offset_;
  std::vector<int> adjacency_begin_, adjacency_;  // per node: the nodes sharing a point with it, increasing
  std::vector<int> diagonal_;                     // per node a: the position of (a, a) in adjacency_
  std::vector<int> transpose_;                    // per position of (a, b): that of (b, a)
  std::vector<int> node_point_begin_, node_point_, node_point_entry_;  // per node: covering points, increasing, and the node's entry
};

extern template class MeshlessElasticTerm<3>;

}  // namespace tailor
