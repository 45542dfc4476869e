#pragma once
// Stretching energy of a discrete elastic rod (Bergou 2010 eq. 2, per edge j):
//   E_s = sum_j 1/2 E_j A(r_j) (|e^j| - L_j)^2 / L_j,
// e^j = x_{j+1} - x_j the current edge, L_j its rest length, E_j Young's modulus and
// A(r_j) = a_coef r_j^2 the cross-section area (cross_section.hpp). Units: energy =
// pressure * length^3. Parameters: the rod's youngs_modulus, radius and rest_length blocks.
#include <memory>

#include "forward/rods/rod_parameters.hpp"
#include "forward/rods/rod_stencil_term.hpp"

namespace tailor {

class RodStretchingTerm final : public rod_detail::RodStencilTerm<RodStretchingTerm, 6, 1, 3> {
 public:
  RodStretchingTerm(std::shared_ptr<const DiscreteRod> rod, CrossSection section, RodParameterBlocks blocks);
  // Out of line: the key function, so the vtable (and the stencil loop) lives in the .cpp.
  std::string name() const override;

  int num_stencils() const { return rod_->num_edges(); }
  std::array<int, 6> stencil_dofs(int edge) const;
  std::array<int, 3> stencil_parameters(int edge) const;  // E, r, L
  std::array<Dual2<6>, 1> strains(const Eigen::Matrix<double, 6, 1>& local, int edge) const;
  void prepare(const Vector&, int) const {}  // no shared per-edge data
  std::array<rod_detail::Dual1<6>, 1> strain_gradients(const Eigen::Matrix<double, 6, 1>& local, int edge) const;
  Eigen::Matrix<double, 1, 1> strain_values(const Eigen::Matrix<double, 6, 1>& local, int edge) const;
  rod_detail::StencilEnergy<1, 3> energy_density(const Eigen::Matrix<double, 1, 1>& length,
                                                 const Eigen::Vector3d& q, int edge) const;

 private:
  std::shared_ptr<const DiscreteRod> rod_;
  CrossSection section_;
  RodParameterBlocks blocks_;
};

// The stencil loop (value, gradient, Hessian, parameter derivatives with Dual2 numbers) is
// instantiated once, in stretching_term.cpp: includers of this header only call it.
extern template class rod_detail::RodStencilTerm<RodStretchingTerm, 6, 1, 3>;

}  // namespace tailor
