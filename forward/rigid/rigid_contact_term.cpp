// The IPC barrier between rigid bodies by the chain rule (see rigid_contact_term.hpp).
#include "forward/rigid/rigid_contact_term.hpp"

#include <algorithm>
#include <stdexcept>

#include "forward/contact/psd_projection.hpp"

namespace tailor::rigid {

RigidContactTerm::RigidContactTerm(const RigidBodySystem& system, contact::ContactOptions options)
    : system_(system), potential_(system.surface(), system.world_positions(system.initial_state()), options) {
  std::vector<int> all(static_cast<std::size_t>(system.num_dofs()));
  for (int i = 0; i < system.num_dofs(); ++i) all[static_cast<std::size_t>(i)] = i;
  slots_.add_block(all);
}

void RigidContactTerm::hessian_pattern(HessianPattern& pattern) const {
  pattern.insert(pattern.end(), slots_.pattern().begin(), slots_.pattern().end());
}

void RigidContactTerm::evaluate(const Vector& q, const Vector& p, const EnergyRequest& request) const {
  (void)p;
  if (request.hessian_values) std::fill(request.hessian_values, request.hessian_values + slots_.size(), 0.0);
  const bool derivatives = request.gradient || request.hessian_values;
  if (!request.value && !derivatives) return;
  const contact::Positions x = system_.world_positions(q);
  std::vector<RotationDerivatives> rotations;
  if (derivatives)
    for (int b = 0; b < system_.num_bodies(); ++b)
      rotations.push_back(rotation_derivatives(q.segment<3>(6 * b + 3)));

  using StencilJacobian = Eigen::Matrix<double, 12, Eigen::Dynamic, 0, 12, 24>;
  double energy = 0.0;
  potential_.for_each_active(x, derivatives, [&](const contact::ActivePair& pair) {
    energy += pair.derivatives.value;
    if (!derivatives) return;
    // The bodies of the stencil, in order of appearance.
    std::array<int, 4> bodies{-1, -1, -1, -1}, column{};
    int count = 0;
    for (int k = 0; k < 4; ++k) {
      const int b = system_.body_of(pair.vertices[static_cast<std::size_t>(k)]);
      const int* found = std::find(bodies.data(), bodies.data() + count, b);
      if (found == bodies.data() + count) bodies[static_cast<std::size_t>(count++)] = b;
      column[static_cast<std::size_t>(k)] =
          static_cast<int>(std::find(bodies.data(), bodies.data() + count, b) - bodies.data());
    }
    StencilJacobian J = StencilJacobian::Zero(12, 6 * count);
    for (int k = 0; k < 4; ++k) {
      const int v = pair.vertices[static_cast<std::size_t>(k)], c = column[static_cast<std::size_t>(k)];
      const RotationDerivatives& r = rotations[static_cast<std::size_t>(system_.body_of(v))];
      const Eigen::Vector3d V = system_.body_frame(v);
      J.block<3, 3>(3 * k, 6 * c).setIdentity();
      for (int l = 0; l < 3; ++l)
        J.block<3, 1>(3 * k, 6 * c + 3 + l) = r.first[static_cast<std::size_t>(l)] * V;
    }
    std::vector<int> dofs;
    for (int c = 0; c < count; ++c)
      for (int i = 0; i < 6; ++i) dofs.push_back(6 * bodies[static_cast<std::size_t>(c)] + i);
    if (request.gradient) {
      const Eigen::VectorXd g = J.transpose() * pair.derivatives.gradient;
      for (int i = 0; i < g.size(); ++i) (*request.gradient)[dofs[static_cast<std::size_t>(i)]] += g[i];
    }
    if (!request.hessian_values) return;
    Eigen::MatrixXd H = J.transpose() * pair.derivatives.hessian * J;
    for (int k = 0; k < 4; ++k) {
      const int v = pair.vertices[static_cast<std::size_t>(k)], c = column[static_cast<std::size_t>(k)];
      const RotationDerivatives& r = rotations[static_cast<std::size_t>(system_.body_of(v))];
      const Eigen::Vector3d V = system_.body_frame(v);
      const Eigen::Vector3d gk = pair.derivatives.gradient.segment<3>(3 * k);
      for (int l = 0; l < 3; ++l)
        for (int m = 0; m < 3; ++m)
          H(6 * c + 3 + l, 6 * c + 3 + m) +=
              gk.dot(r.second[static_cast<std::size_t>(l)][static_cast<std::size_t>(m)] * V);
    }
    if (request.hessian_mode == HessianMode::projected) contact::project_to_psd<Eigen::Dynamic>(H);
    for (int i = 0; i < H.rows(); ++i)
      for (int j = 0; j < H.cols(); ++j)
        request.hessian_values[slots_.slot(dofs[static_cast<std::size_t>(i)],
                                           dofs[static_cast<std::size_t>(j)])] += H(i, j);
  });
  if (request.value) *request.value += energy;
}

double RigidContactTerm::max_step(const Vector& q, const Vector& dq) const {
  const contact::Positions x = system_.world_positions(q);
  const int n = system_.surface().num_vertices;
  Eigen::VectorXd bound(n);  // path length bound of each vertex over t in [0, 1]
  for (int v = 0; v < n; ++v) {
    const int b = system_.body_of(v);
    bound[v] = dq.segment<3>(6 * b).norm() + dq.segment<3>(6 * b + 3).norm() * system_.body_frame(v).norm();
  }
  const contact::CandidatePairs candidates =
      contact::find_candidates(system_.surface(), x, 0.0, nullptr, &bound);
  double step = 1.0;
  auto run = [&](contact::PairKind kind, const std::array<int, 2>& candidate) {
    const std::array<int, 4> v = potential_.stencil(kind, candidate);
    const contact::StencilPath path = [&](double t, std::array<contact::Point, 4>& points) {
      for (int k = 0; k < 4; ++k) {
        const int b = system_.body_of(v[static_cast<std::size_t>(k)]);
        const Eigen::Vector3d T = q.segment<3>(6 * b) + t * dq.segment<3>(6 * b);
        const Eigen::Vector3d w = q.segment<3>(6 * b + 3) + t * dq.segment<3>(6 * b + 3);
        points[static_cast<std::size_t>(k)] =
            T + rotation_matrix(w) * system_.body_frame(v[static_cast<std::size_t>(k)]);
      }
    };
    auto L = [&](int k) { return bound[v[static_cast<std::size_t>(k)]]; };
    const double rate = kind == contact::PairKind::point_triangle
                            ? L(0) + std::max({L(1), L(2), L(3)})
                            : std::max(L(0), L(1)) + std::max(L(2), L(3));
    step = std::min(step, contact::additive_ccd(kind, path, rate, step, potential_.options().ccd));
  };
  for (const auto& c : candidates.point_triangle) run(contact::PairKind::point_triangle, c);
  for (const auto& c : candidates.edge_edge) run(contact::PairKind::edge_edge, c);
  return step;
}

double RigidContactTerm::min_distance(const Vector& q, double range) const {
  return potential_.min_distance(system_.world_positions(q), range);
}

}  // namespace tailor::rigid
