#include "forward/rods/end_moment_term.hpp"

#include <stdexcept>

#include "forward/rods/rod_kinematics.hpp"
#include "forward/rods/rod_stencil_term.hpp"
#include "forward/rods/rod_stencils.hpp"

namespace tailor {

RodEndMomentTerm::RodEndMomentTerm(const DiscreteRod& rod, int edge, const Eigen::Vector3d& axis,
                                   double moment)
    : moment_(moment) {
  if (edge < 0 || edge >= rod.num_edges()) throw std::invalid_argument("RodEndMomentTerm: edge out of range");
  if (!(axis.norm() > 0.0)) throw std::invalid_argument("RodEndMomentTerm: zero axis");
  dofs_ = rod_detail::edge_dofs(rod, edge);
  axis_ = axis.normalized();
  const Eigen::Vector3d e = rod.rest_positions().row(rod.edge_end(edge)) - rod.rest_positions().row(edge);
  direction_ = e - e.dot(axis_) * axis_;
  if (!(direction_.norm() > 1e-12 * e.norm()))
    throw std::invalid_argument("RodEndMomentTerm: the edge is parallel to the moment's axis");
  direction_.normalize();
}

namespace {
Dual2<6> edge_angle(const Eigen::Matrix<double, 6, 1>& local, const Eigen::Vector3d& n,
                    const Eigen::Vector3d& d, double stored) {
  using D = Dual2<6>;
  rod_detail::Dual2Vec3<6> e;
  for (int k = 0; k < 3; ++k) e[k] = D::variable(local[3 + k], 3 + k) - D::variable(local[k], k);
  D phi = atan2(rod_detail::dot(n.cross(d).eval(), e) * 1.0, rod_detail::dot(d, e));
  phi.v += rod_detail::nearest_branch_shift(phi.v, stored);
  return phi;
}
}  // namespace

double RodEndMomentTerm::angle(const Vector& x) const {
  Eigen::Matrix<double, 6, 1> local;
  for (int r = 0; r < 6; ++r) local[r] = x[dofs_[static_cast<std::size_t>(r)]];
  return edge_angle(local, axis_, direction_, stored_angle_).v;
}

void RodEndMomentTerm::evaluate(const Vector& x, const Vector&, const EnergyRequest& request) const {
  Eigen::Matrix<double, 6, 1> local;
  for (int r = 0; r < 6; ++r) local[r] = x[dofs_[static_cast<std::size_t>(r)]];
  const auto phi = edge_angle(local, axis_, direction_, stored_angle_);
  if (request.value) *request.value -= moment_ * phi.v;
  if (request.gradient)
    for (int r = 0; r < 6; ++r) (*request.gradient)[dofs_[static_cast<std::size_t>(r)]] -= moment_ * phi.g[r];
  if (request.hessian_values) {
    Eigen::Matrix<double, 6, 6> H = -moment_ * phi.h;
    if (request.hessian_mode == HessianMode::projected) project_psd(H);
    std::copy(H.data(), H.data() + 36, request.hessian_values);
  }
}

void RodEndMomentTerm::hessian_pattern(HessianPattern& pattern) const {
  for (int c = 0; c < 6; ++c)
    for (int r = 0; r < 6; ++r)
      pattern.push_back({dofs_[static_cast<std::size_t>(r)], dofs_[static_cast<std::size_t>(c)]});
}

}  // namespace tailor
