#pragma once
// Hyperelastic energy of a principal-stretch spline material whose curve control values are
// model parameters (Xu, Sin, Zhu, Barbic 2015):
//   E(x, p) = sum_e V_e Psi(F_e(x); c),   c = p[control_offset, control_offset + num_controls),
// c = [f controls; g controls; h controls] (PrincipalStretchCurves::controls()). The knots of the
// three curves are fixed at construction. One term per material region: give each region its
// element list and its own control block (or share a block between regions).
// Psi is linear in c, so dE/dp and d2E/dxdp are exact and cheap (4 controls per curve per point).
#include <vector>

#include "forward/core/energy_term.hpp"
#include "forward/fem/linear_simplices.hpp"
#include "forward/fem/materials/principal_stretch_curves.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor {

template <int Dim>
class SplineElasticTerm final : public EnergyTerm {
 public:
  static constexpr int kLocal = LinearSimplices<Dim>::kLocal;

  // `knots`: the grids of f, g, h (their control values are not used). Throws
  // std::invalid_argument as ElasticTerm does for bad meshes or element lists.
  SplineElasticTerm(const Mesh& mesh, PrincipalStretchCurves knots, int control_offset,
                    std::vector<int> elements = {});

  std::string name() const override { return "elastic(spline)"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;
  void add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const override;
  void add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const override;
  void add_mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w,
                                 Vector& gradient_p) const override;

  int control_offset() const { return control_offset_; }
  int num_controls() const { return knots_.num_controls(); }
  // The curves with the control values read from p.
  PrincipalStretchCurves curves(const Vector& p) const;
  const std::vector<int>& elements() const { return simplices_.elements; }

 private:
  PrincipalStretchCurves knots_;
  int control_offset_;
  LinearSimplices<Dim> simplices_;
};

extern template class SplineElasticTerm<2>;
extern template class SplineElasticTerm<3>;

}  // namespace tailor
