#pragma once
// Hyperelastic energy of quadratic simplicial elements (10-node tets in 3D, 6-node triangles in
// plane strain; forward/mesh/quadratic_mesh.hpp), the locking-free counterpart of ElasticTerm
// for nearly incompressible solids (docs/materials.md, "Quadratic elements"):
//   E(x, p) = sum_e sum_q w_q |det J_q| Psi(F_e(xi_q, x); lambda(E_e, nu_e), mu(E_e, nu_e)),
// F_e(xi, x) = sum_a x_a grad(N_a)(xi)^T linear in xi on straight-sided elements, q over the
// degree-2 rule of forward/fem/quadratic_simplices.hpp (3 points per triangle, 4 per tet).
// Parameters as ElasticTerm's: the per-element Young's modulus E_e = p[youngs_offset + e] and
// Poisson's ratio nu_e = p[poisson_offset + e], e the element's index in the mesh, so a model
// switches between linear and quadratic elements without touching its parameter layout.
// Every registered material works; the materials' closed-form linear-simplex Hessians do not
// apply, the exact Hessian is sum_q w_q B_q^T T_q B_q with the material's tangent T_q.
#include <memory>
#include <vector>

#include "forward/core/energy_term.hpp"
#include "forward/fem/material.hpp"
#include "forward/fem/quadratic_simplices.hpp"
#include "forward/mesh/quadratic_mesh.hpp"

namespace tailor {

template <int Dim>
class QuadraticElasticTerm final : public EnergyTerm {
 public:
  static constexpr int kNodes = QuadraticSimplices<Dim>::kNodes;
  static constexpr int kLocal = QuadraticSimplices<Dim>::kLocal;
  static constexpr int kPoints = QuadraticSimplices<Dim>::kPoints;

  // `elements`: the mesh elements this term covers (all when empty). Throws
  // std::invalid_argument when the mesh dimension is not Dim or an element is degenerate.
  QuadraticElasticTerm(const QuadraticMesh& mesh, std::shared_ptr<const Material<Dim>> material, int youngs_offset,
                       int poisson_offset, std::vector<int> elements = {});

  std::string name() const override { return "quadratic_elastic(" + material_->name() + ")"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;
  bool hessian_is_constant() const override { return material_->tangent_is_constant(); }
  void add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const override;
  void add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const override;
  void add_mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w,
                                 Vector& gradient_p) const override;
  bool share_by_elements(const std::function<bool(const int* dofs, int count)>& keep,
                         std::unique_ptr<EnergyTerm>& share) const override;

  // First Piola-Kirchhoff stress per covered element (rows in elements() order, row-major
  // Dim x Dim): the element's mean, sum_q w_q P(F_q) / sum_q w_q, for outputs.
  Eigen::MatrixXd stresses(const Vector& x, const Vector& p) const;

  // Deformation gradient at quadrature point q of covered element k (index into elements()).
  Eigen::Matrix<double, Dim, Dim> deformation_gradient(const Vector& x, int k, int q) const {
    return simplices_.field_gradient(x, k, q);
  }
  const std::vector<int>& elements() const { return simplices_.elements; }
  const QuadraticSimplices<Dim>& simplices() const { return simplices_; }
  const Material<Dim>& material() const { return *material_; }

 private:
  QuadraticElasticTerm(std::shared_ptr<const Material<Dim>> material, int youngs_offset, int poisson_offset,
                       QuadraticSimplices<Dim> simplices);
  LameParameters lame(const Vector& p, int element) const;
  Eigen::Matrix2d lame_chain(const Vector& p, int element) const;  // d(lambda, mu)/d(E, nu)
  std::shared_ptr<const Material<Dim>> material_;
  int youngs_offset_, poisson_offset_;
  QuadraticSimplices<Dim> simplices_;
};

extern template class QuadraticElasticTerm<2>;
extern template class QuadraticElasticTerm<3>;

}  // namespace tailor
