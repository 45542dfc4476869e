#pragma once
// Twisting energy of a discrete elastic rod (Bergou 2008 eq. 5, Bergou 2010 section 4.2),
// per interior vertex i:
//   E_t = sum_i GJ_i (m_i - mbar_i)^2 / lbar_i,   m_i = theta^i - theta^{i-1} + m_ref,i,
// m_ref,i the reference twist (angle about t^i from the space-parallel transport of a1^{i-1}
// to a1^i, unwrapped to the branch of the last update, so many turns are tracked),
// GJ_i = (G_{i-1} J(r_{i-1}) + G_i J(r_i)) / 2, J(r) = j_coef r^4, lbar_i = L_{i-1} + L_i.
// Exact derivatives for the stored frames (see bending_term.hpp and docs/rods.md).
// Parameters: shear_modulus, radius, rest_length and rest_twist blocks.
#include <memory>
#include <vector>

#include "forward/rods/cross_edge_products.hpp"
#include "forward/rods/rod_kinematics.hpp"
#include "forward/rods/rod_parameters.hpp"
#include "forward/rods/rod_stencil_term.hpp"

namespace tailor {

class RodTwistingTerm final
    : public rod_detail::RodStencilTerm<RodTwistingTerm, rod_detail::kBendTwistDofs, 1, 7> {
 public:
  using Local = rod_detail::BendTwistLocal;
  RodTwistingTerm(std::shared_ptr<const DiscreteRod> rod, CrossSection section, RodParameterBlocks blocks);
  // Out of line: the key function, so the vtable (and the stencil loop) lives in the .cpp.
  std::string name() const override;

  int num_stencils() const { return rod_->num_interior(); }
  std::array<int, rod_detail::kBendTwistDofs> stencil_dofs(int interior) const;
  // mbar, G_{i-1}, G_i, r_{i-1}, r_i, L_{i-1}, L_i
  std::array<int, 7> stencil_parameters(int interior) const;
  std::array<rod_detail::BendTwistDual, 1> strains(const Local& local, int interior) const;
  // The edges' frames at x, shared by the two stencils at each edge (rod_stencils.hpp).
  void prepare(const Vector& x, int order) const;
  std::array<rod_detail::BendTwistDual1, 1> strain_gradients(const Local& local, int interior) const;
  Eigen::Matrix<double, 1, 1> strain_values(const Local& local, int interior) const;
  // w d2m/dx2 from cross-edge products (forward/rods/cross_edge_products.hpp).
  Eigen::Matrix<double, rod_detail::kBendTwistDofs, rod_detail::kBendTwistDofs> strain_hessian_sum(
      const Local& local, int interior, const Eigen::Matrix<double, 1, 1>& w) const;
  rod_detail::StencilEnergy<1, 7> energy_density(const Eigen::Matrix<double, 1, 1>& twist,
                                                 const Eigen::Matrix<double, 7, 1>& q, int interior) const;

 private:
  std::shared_ptr<const DiscreteRod> rod_;
  CrossSection section_;
  RodParameterBlocks blocks_;
  mutable std::vector<rod_detail::EdgeFrameOf<Dual2<3>>> frames2_;
  mutable std::vector<rod_detail::EdgeFrameOf<rod_detail::Dual1<3>>> frames1_;
  mutable std::vector<rod_detail::ReferenceFrameVectors> reference_frames_;
};

// The stencil loop (value, gradient, Hessian, parameter derivatives with Dual2 numbers) is
// instantiated once, in twisting_term.cpp: includers of this header only call it.
extern template class rod_detail::RodStencilTerm<RodTwistingTerm, rod_detail::kBendTwistDofs, 1, 7>;

}  // namespace tailor
