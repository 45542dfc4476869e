// The IPC barrier on implicit torus distances (see torus_contact_term.hpp).
#include "forward/tori/torus_contact_term.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "forward/contact/barrier.hpp"
#include "forward/core/psd_projection.hpp"

namespace tailor::tori {
namespace {

// The sum of both bounding radii R + max(r, r1), summed left to right as R_a + r_a + R_b + r_b
// for circular tori (the same rounding as before elliptic tubes).
double pair_reach(const TorusShape& a, const TorusShape& b) {
  return a.major_radius + std::max(a.minor_radius, axial_radius(a)) + b.major_radius +
         std::max(b.minor_radius, axial_radius(b));
}

std::string pair_name(int a, int b) { return "tori " + std::to_string(a) + " and " + std::to_string(b); }

}  // namespace

contact::ScalarDerivatives pair_barrier(double d, double d_hat, double kappa) {
  contact::ScalarDerivatives out;
  if (!(d > 0.0)) {
    out.value = std::numeric_limits<double>::infinity();
    return out;
  }
  const contact::ScalarDerivatives b = contact::barrier(d * d, d_hat * d_hat);
  out.value = kappa * b.value;
  out.first = kappa * 2.0 * d * b.first;
  out.second = kappa * (4.0 * d * d * b.second + 2.0 * b.first);
  return out;
}

TorusContactTerm::TorusContactTerm(const rigid::RigidBodySystem& system, std::vector<TorusShape> shapes,
                                   TorusContactOptions options)
    : system_(system), shapes_(std::move(shapes)), options_(options) {
  const int n = system.num_bodies();
  if (static_cast<int>(shapes_.size()) != n)
    throw std::invalid_argument("TorusContactTerm: " + std::to_string(shapes_.size()) + " shapes for " +
                                std::to_string(n) + " bodies");
  for (int i = 0; i < n; ++i)
    validate_shape(shapes_[static_cast<std::size_t>(i)], "TorusContactTerm: torus " + std::to_string(i));
  if (!(options_.activation_distance > 0.0) || !(options_.stiffness > 0.0))
    throw std::invalid_argument("TorusContactTerm: activation_distance and stiffness must be positive");
  if (options_.pair_band < 0) throw std::invalid_argument("TorusContactTerm: pair_band must be >= 0");
  if (!(options_.ccd_fraction > 0.0 && options_.ccd_fraction < 1.0))
    throw std::invalid_argument("TorusContactTerm: ccd_fraction must lie in (0, 1)");
  if (options_.placement_offset < -1)
    throw std::invalid_argument("TorusContactTerm: placement_offset must be >= -1");
  placement_index_.assign(static_cast<std::size_t>(n), -1);
  for (int i = 0; i < n; ++i)
    if (system.body(i).fixed) placement_index_[static_cast<std::size_t>(i)] = num_placements_++;
  pair_slot_.assign(static_cast<std::size_t>(n) * static_cast<std::size_t>(n), -1);
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b) {
      if (options_.pair_band > 0 && b - a > options_.pair_band) continue;
      if (system.body(a).fixed && system.body(b).fixed) continue;
      pair_slot_[static_cast<std::size_t>(a * n + b)] = num_slots_;
      num_slots_ += 144;
    }
}

bool TorusContactTerm::is_candidate(int a, int b) const { return pair_slot(a, b) >= 0; }

int TorusContactTerm::pair_slot(int a, int b) const {
  if (a > b) std::swap(a, b);
  return pair_slot_[static_cast<std::size_t>(a * num_tori() + b)];
}

TorusShape TorusContactTerm::shape(int i, const Vector& p) const {
  if (options_.parameter_offset < 0) return shapes_[static_cast<std::size_t>(i)];
  const int k = options_.parameter_offset + 2 * i;
  if (k + 1 >= p.size())
    throw std::invalid_argument("TorusContactTerm: the parameter vector has " + std::to_string(p.size()) +
                                " entries, torus " + std::to_string(i) + " reads " + std::to_string(k + 1));
  TorusShape s = shapes_[static_cast<std::size_t>(i)];  // r1 is not a parameter: it stays
  s.major_radius = p[k];
  s.minor_radius = p[k + 1];
  return s;
}

TorusPose TorusContactTerm::pose(int i, const Vector& q, const Vector& p) const {
  if (!placed_by_parameters(i)) return {q.segment<3>(6 * i), q.segment<3>(6 * i + 3), shape(i, p)};
  const int k = options_.placement_offset + 6 * placement_index_[static_cast<std::size_t>(i)];
  if (k + 5 >= p.size())
    throw std::invalid_argument("TorusContactTerm: the parameter vector has " + std::to_string(p.size()) +
                                " entries, the placement of fixed torus " + std::to_string(i) + " reads " +
                                std::to_string(k + 5));
  return {p.segment<3>(k), p.segment<3>(k + 3), shape(i, p)};
}

void TorusContactTerm::hessian_pattern(HessianPattern& pattern) const {
  const int n = num_tori();
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b) {
      if (pair_slot_[static_cast<std::size_t>(a * n + b)] < 0) continue;
      for (int i = 0; i < 12; ++i)
        for (int j = 0; j < 12; ++j)
          pattern.push_back({(i < 6 ? 6 * a + i : 6 * b + i - 6), (j < 6 ? 6 * a + j : 6 * b + j - 6)});
    }
}

std::vector<TorusPair> TorusContactTerm::close_pairs(const Vector& q, const Vector& p, double range,
                                                     bool derivatives) const {
  const int n = num_tori();
  std::vector<TorusPose> poses;
  for (int i = 0; i < n; ++i) poses.push_back(pose(i, q, p));
  std::vector<TorusPair> out;
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b) {
      if (system_.body(a).fixed && system_.body(b).fixed) continue;
      const TorusShape &sa = poses[static_cast<std::size_t>(a)].shape,
                       &sb = poses[static_cast<std::size_t>(b)].shape;
      const double reach = pair_reach(sa, sb) + range;
      if ((poses[static_cast<std::size_t>(a)].position - poses[static_cast<std::size_t>(b)].position)
              .norm() >= reach)
        continue;
      TorusPair pair;
      pair.a = a;
      pair.b = b;
      pair.distance = torus_distance(poses[static_cast<std::size_t>(a)], poses[static_cast<std::size_t>(b)],
                                     derivatives, options_.distance);
      if (pair.distance.distance < range) out.push_back(pair);
    }
  return out;
}

double TorusContactTerm::min_distance(const Vector& q, const Vector& p, double range) const {
  double best = std::numeric_limits<double>::infinity();
  for (const TorusPair& pair : close_pairs(q, p, range, false)) best = std::min(best, pair.distance.distance);
  return best;
}

std::vector<TorusPairForce> TorusContactTerm::pair_forces(const Vector& q, const Vector& p) const {
  std::vector<TorusPairForce> out;
  const double d_hat = options_.activation_distance;
  for (const TorusPair& pair : close_pairs(q, p, d_hat, true)) {
    const contact::ScalarDerivatives e = pair_barrier(pair.distance.distance, d_hat, options_.stiffness);
    TorusPairForce f;
    f.a = pair.a;
    f.b = pair.b;
    f.distance = pair.distance.distance;
    f.force_on_b = -e.first * pair.distance.gradient.segment<3>(6);
    out.push_back(f);
  }
  return out;
}

int TorusContactTerm::active_pairs(const Vector& q, const Vector& p) const {
  return static_cast<int>(close_pairs(q, p, options_.activation_distance, false).size());
}

void TorusContactTerm::evaluate(const Vector& q, const Vector& p, const EnergyRequest& request) const {
  if (request.hessian_values) std::fill(request.hessian_values, request.hessian_values + num_slots_, 0.0);
  const bool derivatives = request.gradient || request.hessian_values;
  if (!request.value && !derivatives) return;
  const double d_hat = options_.activation_distance;
  double energy = 0.0;
  for (const TorusPair& pair : close_pairs(q, p, d_hat, derivatives)) {
    const contact::ScalarDerivatives e = pair_barrier(pair.distance.distance, d_hat, options_.stiffness);
    energy += e.value;
    if (!derivatives || !std::isfinite(e.value)) continue;
    if (pair.distance.degenerate)
      throw std::runtime_error(
          "torus_contact: " + pair_name(pair.a, pair.b) +
          " have a degenerate closest-point set (coaxial core circles, or a flat minimum of an "
          "elliptic pair): no derivatives");
    const int a = pair.a, b = pair.b;
    // A torus placed by p has no dependence on its q entries: its rows and columns are zero.
    const bool placed_a = placed_by_parameters(a), placed_b = placed_by_parameters(b);
    const Eigen::Matrix<double, 12, 1> g = e.first * pair.distance.gradient.head<12>();
    if (request.gradient) {
      if (!placed_a) request.gradient->segment<6>(6 * a) += g.head<6>();
      if (!placed_b) request.gradient->segment<6>(6 * b) += g.tail<6>();
    }
    if (request.hessian_values) {
      const int slot = pair_slot_[static_cast<std::size_t>(a * num_tori() + b)];
      if (slot < 0)
        throw std::runtime_error("torus_contact: " + pair_name(a, b) +
                                 " came within the activation distance but are not a candidate pair "
                                 "(pair_band " +
                                 std::to_string(options_.pair_band) + ")");
      Eigen::Matrix<double, 12, 12> H =
          e.second * pair.distance.gradient.head<12>() * pair.distance.gradient.head<12>().transpose() +
          e.first * pair.distance.hessian.topLeftCorner<12, 12>();
      for (int end = 0; end < 2; ++end)
        if (end == 0 ? placed_a : placed_b) {
          H.middleRows<6>(6 * end).setZero();
          H.middleCols<6>(6 * end).setZero();
        }
      if (request.hessian_mode == HessianMode::projected) project_psd(H);
      double* out = request.hessian_values + slot;
      for (int i = 0; i < 12; ++i)
        for (int j = 0; j < 12; ++j) *out++ = H(i, j);
    }
  }
  if (request.value) *request.value += energy;
}

int TorusContactTerm::placement_column(int i) const {
  if (!placed_by_parameters(i)) return -1;
  return options_.placement_offset + 6 * placement_index_[static_cast<std::size_t>(i)];
}

void TorusContactTerm::add_param_gradient(const Vector& q, const Vector& p, Vector& gradient_p) const {
  if (options_.parameter_offset < 0 && options_.placement_offset < 0) return;
  const double d_hat = options_.activation_distance;
  for (const TorusPair& pair : close_pairs(q, p, d_hat, true)) {
    const contact::ScalarDerivatives e = pair_barrier(pair.distance.distance, d_hat, options_.stiffness);
    if (!std::isfinite(e.value) || pair.distance.degenerate) continue;
    const PairGradient& g = pair.distance.gradient;
    if (options_.parameter_offset >= 0) {
      const int ka = options_.parameter_offset + 2 * pair.a, kb = options_.parameter_offset + 2 * pair.b;
      gradient_p.segment<2>(ka) += e.first * g.segment<2>(12);
      gradient_p.segment<2>(kb) += e.first * g.segment<2>(14);
    }
    // A placement's derivative is the anchor's (T, w) part of the pair gradient.
    const int ca = placement_column(pair.a), cb = placement_column(pair.b);
    if (ca >= 0) gradient_p.segment<6>(ca) += e.first * g.segment<6>(0);
    if (cb >= 0) gradient_p.segment<6>(cb) += e.first * g.segment<6>(6);
  }
}

void TorusContactTerm::add_mixed(const Vector& q, const Vector& p, Triplets& mixed) const {
  if (options_.parameter_offset < 0 && options_.placement_offset < 0) return;
  const double d_hat = options_.activation_distance;
  for (const TorusPair& pair : close_pairs(q, p, d_hat, true)) {
    const contact::ScalarDerivatives e = pair_barrier(pair.distance.distance, d_hat, options_.stiffness);
    if (!std::isfinite(e.value) || pair.distance.degenerate) continue;
    const PairGradient& g = pair.distance.gradient;
    const PairHessian M = e.second * g * g.transpose() + e.first * pair.distance.hessian;
    // Pair variables 0-5 are a's (T, w), 6-11 b's; a torus placed by p owns no rows, its
    // placement the columns of its six variables.
    const int ends[2] = {pair.a, pair.b};
    const int placement[2] = {placement_column(pair.a), placement_column(pair.b)};
    for (int i = 0; i < 12; ++i) {
      if (placement[i / 6] >= 0) continue;
      const int row = 6 * ends[i / 6] + i % 6;
      if (options_.parameter_offset >= 0)
        for (int j = 0; j < 4; ++j) {
          const int col = options_.parameter_offset + 2 * ends[j / 2] + j % 2;
          if (M(i, 12 + j) != 0.0) mixed.emplace_back(row, col, M(i, 12 + j));
        }
      for (int end = 0; end < 2; ++end)
        if (placement[end] >= 0)
          for (int j = 0; j < 6; ++j)
            if (M(i, 6 * end + j) != 0.0) mixed.emplace_back(row, placement[end] + j, M(i, 6 * end + j));
    }
  }
}

double TorusContactTerm::max_step(const Vector& q, const Vector& dq) const {
  ++ccd_calls;
  // max_step() has no p: it uses the shapes given at construction.
  const int n = num_tori();
  double alpha = 1.0;
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b) {
      if (system_.body(a).fixed && system_.body(b).fixed) continue;
      alpha = pair_max_step(a, b, shapes_[static_cast<std::size_t>(a)], shapes_[static_cast<std::size_t>(b)], q, dq,
                            alpha);
      if (alpha == 0.0) return 0.0;
    }
  return alpha;
}

double TorusContactTerm::pair_max_step(int a, int b, const TorusShape& sa, const TorusShape& sb, const Vector& q,
                                       const Vector& dq, double alpha) const {
  const double keep = 1.0 - options_.ccd_fraction;
  const Eigen::Vector3d dTa = dq.segment<3>(6 * a), dTb = dq.segment<3>(6 * b);
  const double reach = pair_reach(sa, sb);
  const double gap = (q.segment<3>(6 * a) - q.segment<3>(6 * b)).norm() - (dTa - dTb).norm();
  if (gap > reach) return alpha;  // the bounding spheres never meet along the step
  // Circular pairs: the core points' speed (d = D - r_a - r_b); elliptic ones: the surface
  // points', every one within bounding_radius of its centre.
  const bool surfaces = is_elliptic(sa) || is_elliptic(sb);
  const double La = surfaces ? bounding_radius(sa) : sa.major_radius;
  const double Lb = surfaces ? bounding_radius(sb) : sb.major_radius;
  const double L =
      dTa.norm() + dq.segment<3>(6 * a + 3).norm() * La + dTb.norm() + dq.segment<3>(6 * b + 3).norm() * Lb;
  if (!(L > 0.0)) return alpha;
  auto distance_at = [&](double t) {
    ++ccd_queries;
    const Vector qt = q + t * dq;
    return torus_distance({qt.segment<3>(6 * a), qt.segment<3>(6 * a + 3), sa},
                          {qt.segment<3>(6 * b), qt.segment<3>(6 * b + 3), sb}, false, options_.distance)
        .distance;
  };
  const double d0 = distance_at(0.0);
  if (!(d0 > 0.0)) return 0.0;
  const double floor = keep * d0;
  double t = 0.0, d = d0;
  for (int it = 0; it < 200 && t < alpha; ++it) {
    const double dt = (d - floor) / L;  // d >= floor on [t, t + dt]
    if (!(dt > 1e-12 * std::max(t, 1e-300)) && it > 0) break;
    if (t + dt >= alpha) {
      t = alpha;
      break;
    }
    t += dt;
    d = distance_at(t);
  }
  return std::min(alpha, t);
}

}  // namespace tailor::tori
