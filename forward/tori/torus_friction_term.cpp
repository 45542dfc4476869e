// Lagged IPC friction between implicit tori (see torus_friction_term.hpp).
#include "forward/tori/torus_friction_term.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "forward/contact/barrier.hpp"
#include "forward/core/psd_projection.hpp"
#include "forward/rigid/rotation.hpp"
#include "forward/tori/elliptic_distance.hpp"

namespace tailor::tori {
namespace {

using Vector12 = Eigen::Matrix<double, 12, 1>;
using Matrix12 = Eigen::Matrix<double, 12, 12>;

// The closest points of a pair's distance query on the two surfaces (torus_friction_term.hpp).
void closest_points(const TorusPose& a, const TorusPose& b, const TorusDistance& d, Eigen::Vector3d& x_a,
                    Eigen::Vector3d& x_b, Eigen::Vector3d& normal) {
  if (!is_elliptic(a.shape) && !is_elliptic(b.shape)) {
    // d = D - r_a - r_b: the surface points lie on the segment between the core points.
    const Eigen::Vector3d c_a = core_point(a, d.theta_a), c_b = core_point(b, d.theta_b);
    normal = (c_b - c_a).normalized();
    x_a = c_a + a.shape.minor_radius * normal;
    x_b = c_b - b.shape.minor_radius * normal;
    return;
  }
  x_a = surface_point(a, d.theta_a, d.tube_a);
  x_b = surface_point(b, d.theta_b, d.tube_b);
  normal = (x_b - x_a).normalized();
}

}  // namespace

TorusFrictionTerm::TorusFrictionTerm(const rigid::RigidBodySystem& system, const TorusContactTerm& contact,
                                     TorusFrictionOptions options)
    : contact_(contact), options_(options) {
  const contact::FrictionOptions& f = options_.friction;
  if (!(f.coefficient >= 0.0) || !std::isfinite(f.coefficient))
    throw std::invalid_argument("torus_friction: the coefficient mu must be >= 0, got " +
                                std::to_string(f.coefficient));
  if (!(f.velocity_threshold > 0.0) || !std::isfinite(f.velocity_threshold))
    throw std::invalid_argument("torus_friction: the velocity threshold eps_v must be positive, got " +
                                std::to_string(f.velocity_threshold));
  if (contact.options().parameter_offset >= 0 || contact.options().placement_offset >= 0)
    throw std::invalid_argument(
        "torus_friction: the contact term reads radii or placements from the parameters; friction "
        "follows the poses in q with the constructed shapes only");
  if (contact.num_tori() != system.num_bodies())
    throw std::invalid_argument("torus_friction: the contact term has " + std::to_string(contact.num_tori()) +
                                " tori for " + std::to_string(system.num_bodies()) + " bodies");
}

// The contact term's pairs and slot layout.
void TorusFrictionTerm::hessian_pattern(HessianPattern& pattern) const { contact_.hessian_pattern(pattern); }

void TorusFrictionTerm::lag(const Vector& q_lag, const Vector& q_start, double time_step) {
  if (!(time_step > 0.0) || !std::isfinite(time_step))
    throw std::invalid_argument("torus_friction: the time step must be positive, got " +
                                std::to_string(time_step));
  threshold_ = options_.friction.velocity_threshold * time_step;
  pairs_.clear();
  if (options_.friction.coefficient == 0.0) return;
  const double d_hat = contact_.options().activation_distance, kappa = contact_.options().stiffness;
  for (const TorusPair& close : contact_.close_pairs(q_lag, Vector(), d_hat, false)) {
    const TorusDistance& d = close.distance;
    // An overlap or a circle of closest points has no contact point (the barrier term refuses
    // such a state anyway).
    if (!(d.distance > 0.0) || d.degenerate) continue;
    const int slot = contact_.pair_slot(close.a, close.b);
    if (slot < 0)
      throw std::runtime_error("torus_friction: tori " + std::to_string(close.a) + " and " +
                               std::to_string(close.b) + " are within d_hat but not a candidate pair");
    const TorusPose pa = contact_.pose(close.a, q_lag, Vector()),
                    pb = contact_.pose(close.b, q_lag, Vector());
    Eigen::Vector3d x_a, x_b, normal;
    closest_points(pa, pb, d, x_a, x_b, normal);
    TorusFrictionPair pair;
    pair.a = close.a;
    pair.b = close.b;
    pair.distance = d.distance;
    pair.slot = slot;
    pair.normal = normal;
    pair.material_a = rigid::rotation_matrix(pa.rotation).transpose() * (x_a - pa.position);
    pair.material_b = rigid::rotation_matrix(pb.rotation).transpose() * (x_b - pb.position);
    const double s = d.distance * d.distance;
    pair.stencil.normal_force = kappa * std::abs(contact::barrier(s, d_hat * d_hat).first) * 2.0 * d.distance;
    if (!(pair.stencil.normal_force > 0.0)) continue;
    const Eigen::Matrix<double, 3, 2> P = contact::tangent_basis(normal);
    pair.stencil.tangent.setZero();
    pair.stencil.tangent.block<2, 3>(0, 0) = P.transpose();
    pair.stencil.tangent.block<2, 3>(0, 3) = -P.transpose();
    pair.stencil.start.setZero();
    pair.stencil.start.segment<3>(0) =
        q_start.segment<3>(6 * pair.a) +
        rigid::rotation_matrix(q_start.segment<3>(6 * pair.a + 3)) * pair.material_a;
    pair.stencil.start.segment<3>(3) =
        q_start.segment<3>(6 * pair.b) +
        rigid::rotation_matrix(q_start.segment<3>(6 * pair.b + 3)) * pair.material_b;
    pairs_.push_back(pair);
  }
}

std::vector<double> TorusFrictionTerm::slips(const Vector& q) const {
  std::vector<double> out;
  for (const TorusFrictionPair& pair : pairs_) {
    Vector12 x = Vector12::Zero();
    x.segment<3>(0) =
        q.segment<3>(6 * pair.a) + rigid::rotation_matrix(q.segment<3>(6 * pair.a + 3)) * pair.material_a;
    x.segment<3>(3) =
        q.segment<3>(6 * pair.b) + rigid::rotation_matrix(q.segment<3>(6 * pair.b + 3)) * pair.material_b;
    out.push_back((pair.stencil.tangent * (x - pair.stencil.start)).norm());
  }
  return out;
}

std::pair<int, int> TorusFrictionTerm::sliding_and_sticking(const Vector& q) const {
  int sliding = 0, sticking = 0;
  for (double slip : slips(q)) (slip >= threshold_ ? sliding : sticking)++;
  return {sliding, sticking};
}

void TorusFrictionTerm::evaluate(const Vector& q, const Vector& p, const EnergyRequest& request) const {
  (void)p;
  if (request.hessian_values)
    std::fill(request.hessian_values, request.hessian_values + contact_.num_slots(), 0.0);
  if (pairs_.empty()) return;
  const bool derivatives = request.gradient || request.hessian_values;
  const double mu = options_.friction.coefficient;
  double energy = 0.0;
  for (const TorusFrictionPair& pair : pairs_) {
    const int ends[2] = {pair.a, pair.b};
    const Eigen::Vector3d material[2] = {pair.material_a, pair.material_b};
    rigid::RotationDerivatives rotation[2];
    Vector12 x = Vector12::Zero();
    for (int e = 0; e < 2; ++e) {
      const Eigen::Vector3d w = q.segment<3>(6 * ends[e] + 3);
      if (derivatives)
        rotation[e] = rigid::rotation_derivatives(w);
      else
        rotation[e].rotation = rigid::rotation_matrix(w);
      x.segment<3>(3 * e) = q.segment<3>(6 * ends[e]) + rotation[e].rotation * material[e];
    }
    const contact::FrictionDerivatives f =
        contact::friction_pair_potential(pair.stencil, x, mu, threshold_, derivatives);
    energy += f.value;
    if (!derivatives) continue;
    // J: the two points (rows 0-2 a, 3-5 b) in the pair's DOFs (T_a, w_a, T_b, w_b).
    Eigen::Matrix<double, 6, 12> J = Eigen::Matrix<double, 6, 12>::Zero();
    for (int e = 0; e < 2; ++e) {
      J.block<3, 3>(3 * e, 6 * e).setIdentity();
      for (int k = 0; k < 3; ++k)
        J.block<3, 1>(3 * e, 6 * e + 3 + k) = rotation[e].first[static_cast<std::size_t>(k)] * material[e];
    }
    const Eigen::Matrix<double, 6, 1> g_x = f.gradient.head<6>();
    const Vector12 g = J.transpose() * g_x;
    if (request.gradient) {
      request.gradient->segment<6>(6 * pair.a) += g.head<6>();
      request.gradient->segment<6>(6 * pair.b) += g.tail<6>();
    }
    if (!request.hessian_values) continue;
    Matrix12 H = J.transpose() * f.hessian.topLeftCorner<6, 6>() * J;
    if (options_.rotation_curvature)
      for (int e = 0; e < 2; ++e)
        for (int k = 0; k < 3; ++k)
          for (int l = 0; l < 3; ++l)
            H(6 * e + 3 + k, 6 * e + 3 + l) += g_x.segment<3>(3 * e).dot(
                rotation[e].second[static_cast<std::size_t>(k)][static_cast<std::size_t>(l)] * material[e]);
    if (request.hessian_mode == HessianMode::projected) project_psd(H);
    double* out = request.hessian_values + pair.slot;
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 12; ++j) *out++ += H(i, j);
  }
  if (request.value) *request.value += energy;
}

}  // namespace tailor::tori
