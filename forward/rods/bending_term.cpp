#include "forward/rods/bending_term.hpp"

#include <stdexcept>

#include "forward/rods/rod_stencils.hpp"

namespace tailor {

RodBendingTerm::RodBendingTerm(std::shared_ptr<const DiscreteRod> rod, CrossSection section,
                               RodParameterBlocks blocks)
    : rod_(std::move(rod)), section_(section), blocks_(blocks) {
  if (!rod_) throw std::invalid_argument("RodBendingTerm: no rod given");
  section_.validate();
}

std::array<int, rod_detail::kBendTwistDofs> RodBendingTerm::stencil_dofs(int interior) const {
  return rod_detail::bend_twist_dofs(*rod_, interior);
}

std::array<int, 8> RodBendingTerm::stencil_parameters(int i) const {
  const auto& b = blocks_;
  const int k = rod_->next_edge(i);
  return {b.rest_curvature + 2 * i,
          b.rest_curvature + 2 * i + 1,
          b.youngs_modulus + i,
          b.youngs_modulus + k,
          b.radius + i,
          b.radius + k,
          b.rest_length + i,
          b.rest_length + k};
}

void RodBendingTerm::prepare(const Vector& x, int order) const {
  if (!rod_detail::prepare_edge_frames(*rod_, x, order, frames1_, frames2_)) return;
  const int ne = rod_->num_edges();
  material_frames_.resize(static_cast<std::size_t>(ne));
#pragma omp parallel for schedule(static) if (ne > 512)
  for (int j = 0; j < ne; ++j)
    material_frames_[static_cast<std::size_t>(j)] =
        rod_detail::material_frame_vectors(frames2_[static_cast<std::size_t>(j)], x[rod_->twist_dof(j)]);
}

Eigen::Matrix<double, rod_detail::kBendTwistDofs, rod_detail::kBendTwistDofs> RodBendingTerm::strain_hessian_sum(
    const Local&, int interior, const Eigen::Vector2d& w) const {
  return rod_detail::lift_hessian(
      rod_detail::curvature_hessian_sum(material_frames_[static_cast<std::size_t>(interior)],
                                        material_frames_[static_cast<std::size_t>(rod_->next_edge(interior))], w));
}

std::array<rod_detail::BendTwistDual, 2> RodBendingTerm::strains(const Local& local, int interior) const {
  const auto kappa = rod_detail::curvatures_from_frames<Dual2<6>, Dual2<rod_detail::kEdgeVariables>>(
      rod_detail::stencil_frames<Dual2<6>>(frames2_[static_cast<std::size_t>(interior)],
                                           frames2_[static_cast<std::size_t>(rod_->next_edge(interior))]),
      local);
  return {rod_detail::lift(kappa[0]), rod_detail::lift(kappa[1])};
}

// W = sum_a B_a d_a^2 / lbar, d = kappa - kappabar; derivatives in s = kappa and q (see header).
rod_detail::StencilEnergy<2, 8> RodBendingTerm::energy_density(const Eigen::Vector2d& kappa,
                                                               const Eigen::Matrix<double, 8, 1>& q,
                                                               int) const {
  const Eigen::Vector2d d = kappa - q.head<2>();
  const double E0 = q[2], E1 = q[3], r0 = q[4], r1 = q[5], lbar = q[6] + q[7];
  const Eigen::Vector2d c(section_.bending_coefficient1(), section_.bending_coefficient2());
  const double r04 = r0 * r0 * r0 * r0, r14 = r1 * r1 * r1 * r1;
  const Eigen::Vector2d B = 0.5 * (E0 * r04 + E1 * r14) * c;
  rod_detail::StencilEnergy<2, 8> W;
  W.value = (B.array() * d.array().square()).sum() / lbar;
  W.ds = 2.0 * B.cwiseProduct(d) / lbar;
  W.dss = (2.0 * B / lbar).asDiagonal();
  const Eigen::Vector2d d2 = d.cwiseProduct(d) / lbar;  // dW/dB_a
  W.dq.head<2>() = -W.ds;
  W.dq[2] = 0.5 * r04 * c.dot(d2);
  W.dq[3] = 0.5 * r14 * c.dot(d2);
  W.dq[4] = 2.0 * E0 * r0 * r0 * r0 * c.dot(d2);
  W.dq[5] = 2.0 * E1 * r1 * r1 * r1 * c.dot(d2);
  W.dq[6] = W.dq[7] = -W.value / lbar;
  for (int a = 0; a < 2; ++a) {
    W.dsq(a, a) = -2.0 * B[a] / lbar;
    W.dsq(a, 2) = c[a] * r04 * d[a] / lbar;
    W.dsq(a, 3) = c[a] * r14 * d[a] / lbar;
    W.dsq(a, 4) = 4.0 * E0 * c[a] * r0 * r0 * r0 * d[a] / lbar;
    W.dsq(a, 5) = 4.0 * E1 * c[a] * r1 * r1 * r1 * d[a] / lbar;
    W.dsq(a, 6) = W.dsq(a, 7) = -2.0 * B[a] * d[a] / (lbar * lbar);
  }
  return W;
}

std::array<rod_detail::BendTwistDual1, 2> RodBendingTerm::strain_gradients(const Local& local, int interior) const {
  const auto kappa =
      rod_detail::curvatures_from_frames<rod_detail::Dual1<6>, rod_detail::Dual1<rod_detail::kEdgeVariables>>(
          rod_detail::stencil_frames<rod_detail::Dual1<6>>(
              frames1_[static_cast<std::size_t>(interior)],
              frames1_[static_cast<std::size_t>(rod_->next_edge(interior))]),
          local);
  return {rod_detail::lift(kappa[0]), rod_detail::lift(kappa[1])};
}

Eigen::Vector2d RodBendingTerm::strain_values(const Local& local, int interior) const {
  const auto s = rod_detail::bend_twist_strains<rod_detail::Dual0>(local, rod_detail::stored_frames(*rod_, interior));
  return {s.kappa1.v, s.kappa2.v};
}

std::string RodBendingTerm::name() const { return "rod_bending"; }

template class rod_detail::RodStencilTerm<RodBendingTerm, rod_detail::kBendTwistDofs, 2, 8>;

}  // namespace tailor
