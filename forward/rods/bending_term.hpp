#pragma once
// Bending energy of a discrete elastic rod (Bergou 2008 eq. 4 with the anisotropic material
// curvatures of Bergou 2010 section 4.1; docs/rods.md), per interior vertex i:
//   E_b = sum_i sum_{a=1,2} B_a,i (kappa_a,i - kappabar_a,i)^2 / lbar_i,
//   kappa_1 = (kb)_i . (m2^{i-1} + m2^i) / 2,  kappa_2 = -(kb)_i . (m1^{i-1} + m1^i) / 2,
//   (kb)_i = 2 e^{i-1} x e^i / (|e^{i-1}||e^i| + e^{i-1} . e^i),   lbar_i = L_{i-1} + L_i,
//   B_a,i = (E_{i-1} I_a(r_{i-1}) + E_i I_a(r_i)) / 2,  I_a(r) = i_a_coef r^4.
// For a smooth planar curve this is 1/2 int E I kappa^2 ds (|kb| = 2 tan(phi/2) ~ kappa lbar/2).
// The material frame m^j is the time-parallel reference frame of DiscreteRod rotated by the
// twist angle theta^j: the gradient and Hessian are the exact derivatives of this energy for
// the stored frames of the last update_reference_frames() call, including the reference
// frame's dependence on x (docs/rods.md, "Exact Hessian"). Units: energy = pressure length^3.
// Parameters: youngs_modulus, radius, rest_length and rest_curvature blocks.
#include <memory>
#include <vector>

#include "forward/rods/cross_edge_products.hpp"
#include "forward/rods/rod_kinematics.hpp"
#include "forward/rods/rod_parameters.hpp"
#include "forward/rods/rod_stencil_term.hpp"

namespace tailor {

class RodBendingTerm final
    : public rod_detail::RodStencilTerm<RodBendingTerm, rod_detail::kBendTwistDofs, 2, 8> {
 public:
  using Local = rod_detail::BendTwistLocal;
  RodBendingTerm(std::shared_ptr<const DiscreteRod> rod, CrossSection section, RodParameterBlocks blocks);
  // Out of line: the key function, so the vtable (and the stencil loop) lives in the .cpp.
  std::string name() const override;

  int num_stencils() const { return rod_->num_interior(); }
  std::array<int, rod_detail::kBendTwistDofs> stencil_dofs(int interior) const;
  // kappabar_1, kappabar_2, E_{i-1}, E_i, r_{i-1}, r_i, L_{i-1}, L_i
  std::array<int, 8> stencil_parameters(int interior) const;
  std::array<rod_detail::BendTwistDual, 2> strains(const Local& local, int interior) const;
  // The edges' frames at x, shared by the two stencils at each edge (rod_stencils.hpp).
  void prepare(const Vector& x, int order) const;
  std::array<rod_detail::BendTwistDual1, 2> strain_gradients(const Local& local, int interior) const;
  Eigen::Vector2d strain_values(const Local& local, int interior) const;
  // sum_a w_a d2kappa_a/dx2 from cross-edge products (forward/rods/cross_edge_products.hpp).
  Eigen::Matrix<double, rod_detail::kBendTwistDofs, rod_detail::kBendTwistDofs> strain_hessian_sum(
      const Local& local, int interior, const Eigen::Vector2d& w) const;
  rod_detail::StencilEnergy<2, 8> energy_density(const Eigen::Vector2d& kappa,
                                                 const Eigen::Matrix<double, 8, 1>& q, int interior) const;

 private:
  std::shared_ptr<const DiscreteRod> rod_;
  CrossSection section_;
  RodParameterBlocks blocks_;
  mutable std::vector<rod_detail::EdgeFrameOf<Dual2<3>>> frames2_;
  mutable std::vector<rod_detail::EdgeFrameOf<rod_detail::Dual1<3>>> frames1_;
  mutable std::vector<rod_detail::MaterialFrameVectors> material_frames_;
};

// The stencil loop (value, gradient, Hessian, parameter derivatives with Dual2 numbers) is
// instantiated once, in bending_term.cpp: includers of this header only call it.
extern template class rod_detail::RodStencilTerm<RodBendingTerm, rod_detail::kBendTwistDofs, 2, 8>;

}  // namespace tailor
