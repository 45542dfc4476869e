#include "forward/rods/stretching_term.hpp"

#include <stdexcept>

#include "forward/rods/rod_stencils.hpp"

namespace tailor {

RodStretchingTerm::RodStretchingTerm(std::shared_ptr<const DiscreteRod> rod, CrossSection section,
                                     RodParameterBlocks blocks)
    : rod_(std::move(rod)), section_(section), blocks_(blocks) {
  if (!rod_) throw std::invalid_argument("RodStretchingTerm: no rod given");
  section_.validate();
}

std::array<int, 6> RodStretchingTerm::stencil_dofs(int edge) const {
  return rod_detail::edge_dofs(*rod_, edge);
}

std::array<int, 3> RodStretchingTerm::stencil_parameters(int edge) const {
  return {blocks_.youngs_modulus + edge, blocks_.radius + edge, blocks_.rest_length + edge};
}

std::array<Dual2<6>, 1> RodStretchingTerm::strains(const Eigen::Matrix<double, 6, 1>& local, int) const {
  return {rod_detail::edge_length(local)};
}

// W = 1/2 k (l - L)^2 / L with k = E a r^2; derivatives in s = l and q = (E, r, L).
rod_detail::StencilEnergy<1, 3> RodStretchingTerm::energy_density(const Eigen::Matrix<double, 1, 1>& length,
                                                                  const Eigen::Vector3d& q, int) const {
  const double l = length[0], E = q[0], r = q[1], L = q[2];
  const double a = section_.area_coefficient();
  const double A = a * r * r, dA = 2.0 * a * r, k = E * A, d = l - L;
  rod_detail::StencilEnergy<1, 3> W;
  W.value = 0.5 * k * d * d / L;
  W.ds[0] = k * d / L;
  W.dss(0, 0) = k / L;
  W.dq << 0.5 * A * d * d / L, 0.5 * E * dA * d * d / L, -0.5 * k * (l * l / (L * L) - 1.0);
  W.dsq << A * d / L, E * dA * d / L, -k * l / (L * L);
  return W;
}

std::array<rod_detail::Dual1<6>, 1> RodStretchingTerm::strain_gradients(const Eigen::Matrix<double, 6, 1>& local,
                                                                          int) const {
  return {rod_detail::edge_length<rod_detail::Dual1<6>>(local)};
}

Eigen::Matrix<double, 1, 1> RodStretchingTerm::strain_values(const Eigen::Matrix<double, 6, 1>& local,
                                                             int) const {
  return Eigen::Matrix<double, 1, 1>(rod_detail::edge_length<rod_detail::Dual0>(local).v);
}

std::string RodStretchingTerm::name() const { return "rod_stretching"; }

template class rod_detail::RodStencilTerm<RodStretchingTerm, 6, 1, 3>;

}  // namespace tailor
