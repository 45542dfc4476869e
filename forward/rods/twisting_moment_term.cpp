// Twisting moments as a conservative load (see twisting_moment_term.hpp).
#include "forward/rods/twisting_moment_term.hpp"

#include <map>
#include <stdexcept>
#include <string>

#include "forward/core/psd_projection.hpp"
#include "forward/rods/rod_kinematics.hpp"
#include "forward/rods/rod_stencils.hpp"

namespace tailor {

RodTwistingMomentTerm::RodTwistingMomentTerm(std::shared_ptr<const DiscreteRod> rod,
                                             const std::vector<std::pair<int, double>>& moments)
    : rod_(std::move(rod)) {
  std::map<int, double> by_edge;
  for (const auto& [edge, moment] : moments) {
    if (edge < 0 || edge >= rod_->num_edges())
      throw std::out_of_range("rod edge " + std::to_string(edge) + " out of range");
    by_edge[edge] += moment;
  }
  for (const auto& [edge, moment] : by_edge) {
    edges_.push_back(edge);
    moments_.push_back(moment);
    rest_tangents_.push_back(rod_->stored_tangent(edge));
    rest_directors_.push_back(rod_->stored_director(edge));
    stored_delta_.push_back(0.0);
  }
}

namespace {

// delta: the signed angle about t from P(t_0 -> t) a1_0 to the reference director
// P(t_* -> t) a1_*, on the branch nearest `stored`.
Dual2<6> transport_offset(const Eigen::Matrix<double, 6, 1>& local, const Eigen::Vector3d& rest_tangent,
                          const Eigen::Vector3d& rest_director, const Eigen::Vector3d& stored_tangent,
                          const Eigen::Vector3d& stored_director, double stored) {
  using D = Dual2<6>;
  using V = rod_detail::Dual2Vec3<6>;
  V e;
  for (int k = 0; k < 3; ++k) e[k] = D::variable(local[3 + k], 3 + k) - D::variable(local[k], k);
  const V t = reciprocal(rod_detail::norm(e)) * e;
  const V b0 = rod_detail::transport(V::constant(rest_tangent), t, V::constant(rest_director));
  const V a1 = rod_detail::transport(V::constant(stored_tangent), t, V::constant(stored_director));
  D delta = atan2(rod_detail::dot(rod_detail::cross(b0, a1), t), rod_detail::dot(b0, a1));
  delta.v += rod_detail::nearest_branch_shift(delta.v, stored);
  return delta;
}

}  // namespace

double RodTwistingMomentTerm::angle(const Vector& x, int k) const {
  const std::size_t i = static_cast<std::size_t>(k);
  const int j = edges_[i];
  const std::array<int, 6> dofs = rod_detail::edge_dofs(*rod_, j);
  Eigen::Matrix<double, 6, 1> local;
  for (int r = 0; r < 6; ++r) local[r] = x[dofs[static_cast<std::size_t>(r)]];
  return x[rod_->twist_dof(j)] + transport_offset(local, rest_tangents_[i], rest_directors_[i],
                                                  rod_->stored_tangent(j), rod_->stored_director(j),
                                                  stored_delta_[i])
                                     .v;
}

void RodTwistingMomentTerm::update_branches(const Vector& x) {
  for (int k = 0; k < num_moments(); ++k)
    stored_delta_[static_cast<std::size_t>(k)] = angle(x, k) - x[rod_->twist_dof(edges_[static_cast<std::size_t>(k)])];
}

void RodTwistingMomentTerm::evaluate(const Vector& x, const Vector&, const EnergyRequest& request) const {
  for (std::size_t i = 0; i < edges_.size(); ++i) {
    const int j = edges_[i];
    const double M = factor * moments_[i];
    const std::array<int, 6> dofs = rod_detail::edge_dofs(*rod_, j);
    Eigen::Matrix<double, 6, 1> local;
    for (int r = 0; r < 6; ++r) local[r] = x[dofs[static_cast<std::size_t>(r)]];
    const Dual2<6> delta = transport_offset(local, rest_tangents_[i], rest_directors_[i], rod_->stored_tangent(j),
                                            rod_->stored_director(j), stored_delta_[i]);
    if (request.value) *request.value -= M * (x[rod_->twist_dof(j)] + delta.v);
    if (request.gradient) {
      (*request.gradient)[rod_->twist_dof(j)] -= M;
      for (int r = 0; r < 6; ++r) (*request.gradient)[dofs[static_cast<std::size_t>(r)]] -= M * delta.g[r];
    }
    if (request.hessian_values) {
      Eigen::Matrix<double, 6, 6> H = -M * delta.h;
      if (request.hessian_mode == HessianMode::projected) project_psd(H);
      std::copy(H.data(), H.data() + 36, request.hessian_values + 36 * i);
    }
  }
}

void RodTwistingMomentTerm::hessian_pattern(HessianPattern& pattern) const {
  for (int j : edges_) {
    const std::array<int, 6> dofs = rod_detail::edge_dofs(*rod_, j);
    for (int c = 0; c < 6; ++c)
      for (int r = 0; r < 6; ++r)
        pattern.push_back({dofs[static_cast<std::size_t>(r)], dofs[static_cast<std::size_t>(c)]});
  }
}

}  // namespace tailor
