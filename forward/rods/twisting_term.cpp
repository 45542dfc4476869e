#include "forward/rods/twisting_term.hpp"

#include <stdexcept>

#include "forward/rods/rod_stencils.hpp"

namespace tailor {

RodTwistingTerm::RodTwistingTerm(std::shared_ptr<const DiscreteRod> rod, CrossSection section,
                                 RodParameterBlocks blocks)
    : rod_(std::move(rod)), section_(section), blocks_(blocks) {
  if (!rod_) throw std::invalid_argument("RodTwistingTerm: no rod given");
  section_.validate();
}

std::array<int, rod_detail::kBendTwistDofs> RodTwistingTerm::stencil_dofs(int interior) const {
  return rod_detail::bend_twist_dofs(*rod_, interior);
}

std::array<int, 7> RodTwistingTerm::stencil_parameters(int i) const {
  const auto& b = blocks_;
  const int k = rod_->next_edge(i);
  return {b.rest_twist + i, b.shear_modulus + i, b.shear_modulus + k, b.radius + i,
          b.radius + k,     b.rest_length + i,   b.rest_length + k};
}

void RodTwistingTerm::prepare(const Vector& x, int order) const {
  if (!rod_detail::prepare_edge_frames(*rod_, x, order, frames1_, frames2_)) return;
  const int ne = rod_->num_edges();
  reference_frames_.resize(static_cast<std::size_t>(ne));
#pragma omp parallel for schedule(static) if (ne > 512)
  for (int j = 0; j < ne; ++j)
    reference_frames_[static_cast<std::size_t>(j)] =
        rod_detail::reference_frame_vectors(frames2_[static_cast<std::size_t>(j)]);
}

// m = theta^i - theta^{i-1} + m_ref: only m_ref has second derivatives, in the edge coordinates.
Eigen::Matrix<double, rod_detail::kBendTwistDofs, rod_detail::kBendTwistDofs> RodTwistingTerm::strain_hessian_sum(
    const Local&, int interior, const Eigen::Matrix<double, 1, 1>& w) const {
  Eigen::Matrix<double, rod_detail::kEdgeVariables, rod_detail::kEdgeVariables> h =
      Eigen::Matrix<double, rod_detail::kEdgeVariables, rod_detail::kEdgeVariables>::Zero();
  h.topLeftCorner<6, 6>() =
      w[0] * rod_detail::reference_twist_hessian(reference_frames_[static_cast<std::size_t>(interior)],
                                                 reference_frames_[static_cast<std::size_t>(rod_->next_edge(interior))]);
  return rod_detail::lift_hessian(h);
}

std::array<rod_detail::BendTwistDual, 1> RodTwistingTerm::strains(const Local& local, int interior) const {
  const auto raw = rod_detail::reference_twist_of(
      rod_detail::stencil_frames<Dual2<6>>(frames2_[static_cast<std::size_t>(interior)],
                                           frames2_[static_cast<std::size_t>(rod_->next_edge(interior))]),
      rod_detail::stored_frames(*rod_, interior));
  return {rod_detail::twist_from_reference(raw, local)};
}

// W = GJ d^2 / lbar, d = m - mbar; derivatives in s = m and q (see header).
rod_detail::StencilEnergy<1, 7> RodTwistingTerm::energy_density(const Eigen::Matrix<double, 1, 1>& twist,
                                                                const Eigen::Matrix<double, 7, 1>& q,
                                                                int) const {
  const double d = twist[0] - q[0], G0 = q[1], G1 = q[2], r0 = q[3], r1 = q[4], lbar = q[5] + q[6];
  const double c = section_.torsion_coefficient();
  const double r03 = r0 * r0 * r0, r13 = r1 * r1 * r1;
  const double GJ = 0.5 * c * (G0 * r03 * r0 + G1 * r13 * r1);
  rod_detail::StencilEnergy<1, 7> W;
  W.value = GJ * d * d / lbar;
  W.ds[0] = 2.0 * GJ * d / lbar;
  W.dss(0, 0) = 2.0 * GJ / lbar;
  const double dd = d * d / lbar;  // dW/dGJ
  W.dq << -W.ds[0], 0.5 * c * r03 * r0 * dd, 0.5 * c * r13 * r1 * dd, 2.0 * c * G0 * r03 * dd,
      2.0 * c * G1 * r13 * dd, -W.value / lbar, -W.value / lbar;
  W.dsq << -2.0 * GJ / lbar, c * r03 * r0 * d / lbar, c * r13 * r1 * d / lbar, 4.0 * c * G0 * r03 * d / lbar,
      4.0 * c * G1 * r13 * d / lbar, -2.0 * GJ * d / (lbar * lbar), -2.0 * GJ * d / (lbar * lbar);
  return W;
}

std::array<rod_detail::BendTwistDual1, 1> RodTwistingTerm::strain_gradients(const Local& local, int interior) const {
  const auto raw = rod_detail::reference_twist_of(
      rod_detail::stencil_frames<rod_detail::Dual1<6>>(frames1_[static_cast<std::size_t>(interior)],
                                                       frames1_[static_cast<std::size_t>(rod_->next_edge(interior))]),
      rod_detail::stored_frames(*rod_, interior));
  return {rod_detail::twist_from_reference(raw, local)};
}

Eigen::Matrix<double, 1, 1> RodTwistingTerm::strain_values(const Local& local, int interior) const {
  const auto s = rod_detail::bend_twist_strains<rod_detail::Dual0>(local, rod_detail::stored_frames(*rod_, interior));
  return Eigen::Matrix<double, 1, 1>(s.twist.v);
}

std::string RodTwistingTerm::name() const { return "rod_twisting"; }

template class rod_detail::RodStencilTerm<RodTwistingTerm, rod_detail::kBendTwistDofs, 1, 7>;

}  // namespace tailor
