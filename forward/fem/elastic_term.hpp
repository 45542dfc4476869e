#pragma once
// Hyperelastic energy of linear simplicial elements (tets in 3D, triangles in plane strain):
//   E(x, p) = sum_e V_e Psi(F_e(x); lambda(E_e, nu_e), mu(E_e, nu_e)),
// with F_e = sum_a x_a grad(N_a)^T constant per element, V_e the rest volume (area in 2D,
// per unit thickness). Parameters: the per-element Young's modulus E_e = p[youngs_offset + e]
// and Poisson's ratio nu_e = p[poisson_offset + e], e the element's index in the mesh.
#include <memory>
#include <vector>

#include "forward/core/energy_term.hpp"
#include "forward/fem/linear_simplices.hpp"
#include "forward/fem/material.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor {

template <int Dim>
class ElasticTerm final : public EnergyTerm {
 public:
  static constexpr int kNodes = LinearSimplices<Dim>::kNodes;
  static constexpr int kLocal = LinearSimplices<Dim>::kLocal;            // element DOFs
  using ShapeGradients = typename LinearSimplices<Dim>::ShapeGradients;  // row a: grad N_a at rest

  // `elements`: the mesh elements this term covers (all when empty). Throws
  // std::invalid_argument when the mesh dimension is not Dim or an element is degenerate.
  ElasticTerm(const Mesh& mesh, std::shared_ptr<const Material<Dim>> material, int youngs_offset,
              int poisson_offset, std::vector<int> elements = {});

  std::string name() const override { return "elastic(" + material_->name() + ")"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;
  bool hessian_is_constant() const override { return material_->tangent_is_constant(); }
  void add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const override;
  void add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const override;
  void add_mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w,
                                 Vector& gradient_p) const override;
  bool share_by_elements(const std::function<bool(const int* dofs, int count)>& keep,
                         std::unique_ptr<EnergyTerm>& share) const override;

  // Deformation gradient of covered element k (index into elements()) at state x.
  Eigen::Matrix<double, Dim, Dim> deformation_gradient(const Vector& x, int k) const;
  // First Piola-Kirchhoff stress per covered element, row-major Dim*Dim columns.
  Eigen::MatrixXd stresses(const Vector& x, const Vector& p) const;
  const std::vector<int>& elements() const { return simplices_.elements; }
  const Material<Dim>& material() const { return *material_; }
  // Rest shape gradients, rest volume and Lame parameters (from p) of covered element k.
  const ShapeGradients& shape_gradients(int k) const {
    return simplices_.gradients[static_cast<std::size_t>(k)];
  }
  double rest_volume(int k) const { return simplices_.volumes[static_cast<std::size_t>(k)]; }
  const Eigen::Matrix<int, kNodes, 1>& element_vertices(int k) const {
    return simplices_.vertices[static_cast<std::size_t>(k)];
  }
  LameParameters element_lame(const Vector& p, int k) const {
    return lame(p, simplices_.elements[static_cast<std::size_t>(k)]);
  }

 private:
  ElasticTerm(std::shared_ptr<const Material<Dim>> material, int youngs_offset, int poisson_offset,
              LinearSimplices<Dim> simplices);
  LameParameters lame(const Vector& p, int element) const;
  std::shared_ptr<const Material<Dim>> material_;
  bool closed_form_hessian_ = false;  // the material writes the exact element Hessian itself
  int youngs_offset_, poisson_offset_;
  LinearSimplices<Dim> simplices_;
};

extern template class ElasticTerm<2>;
extern template class ElasticTerm<3>;

}  // namespace tailor
