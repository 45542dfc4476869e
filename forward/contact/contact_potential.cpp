// The barrier energy of a contact surface (see contact_potential.hpp).
#include "forward/contact/contact_potential.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "forward/contact/barrier.hpp"

namespace tailor::contact {

ContactPotential::ContactPotential(ContactSurface surface, const Positions& rest, ContactOptions options)
    : surface_(std::move(surface)), options_(options) {
  if (!(options_.activation_distance > 0.0) || !std::isfinite(options_.activation_distance))
    throw std::invalid_argument("contact: activation distance d_hat must be positive and finite, got " +
                                std::to_string(options_.activation_distance));
  set_stiffness(options_.stiffness);
  if (rest.rows() != surface_.num_vertices)
    throw std::invalid_argument("contact: " + std::to_string(rest.rows()) + " rest positions for " +
                                std::to_string(surface_.num_vertices) + " surface vertices");
  edge_rest_length_squared_.resize(static_cast<std::size_t>(surface_.edges.rows()));
  for (int e = 0; e < surface_.edges.rows(); ++e)
    edge_rest_length_squared_[static_cast<std::size_t>(e)] =
        (rest.row(surface_.edges(e, 1)) - rest.row(surface_.edges(e, 0))).squaredNorm();
}

void ContactPotential::set_stiffness(double kappa) {
  if (!(kappa > 0.0) || !std::isfinite(kappa))
    throw std::invalid_argument("contact: stiffness kappa must be positive and finite, got " +
                                std::to_string(kappa));
  options_.stiffness = kappa;
}

std::array<int, 4> ContactPotential::stencil(PairKind kind, const std::array<int, 2>& pair) const {
  if (kind == PairKind::point_triangle)
    return {pair[0], surface_.faces(pair[1], 0), surface_.faces(pair[1], 1), surface_.faces(pair[1], 2)};
  return {surface_.edges(pair[0], 0), surface_.edges(pair[0], 1), surface_.edges(pair[1], 0),
          surface_.edges(pair[1], 1)};
}

double ContactPotential::mollifier_eps(const std::array<int, 2>& edge_pair) const {
  return mollifier_threshold(edge_rest_length_squared_[static_cast<std::size_t>(edge_pair[0])],
                             edge_rest_length_squared_[static_cast<std::size_t>(edge_pair[1])]);
}

namespace {
std::array<Point, 4> points_of(const Positions& x, const std::array<int, 4>& v) {
  return {x.row(v[0]).transpose(), x.row(v[1]).transpose(), x.row(v[2]).transpose(), x.row(v[3]).transpose()};
}
}  // namespace

void ContactPotential::for_each_active(const Positions& x, bool derivatives,
                                       const std::function<void(const ActivePair&)>& visit) const {
  const double d_hat = options_.activation_distance, s_hat = d_hat * d_hat, kappa = options_.stiffness;
  const CandidatePairs candidates = find_candidates(surface_, x, d_hat);
  ActivePair active;
  auto run = [&](PairKind kind, const std::array<int, 2>& pair) {
    active.kind = kind;
    active.vertices = stencil(kind, pair);
    const double eps = kind == PairKind::edge_edge ? mollifier_eps(pair) : 0.0;
    if (!pair_barrier(kind, points_of(x, active.vertices), s_hat, eps, derivatives, active.derivatives))
      return;
    active.derivatives.value *= kappa;
    active.derivatives.gradient *= kappa;
    active.derivatives.hessian *= kappa;
    visit(active);
  };
  for (const auto& pair : candidates.point_triangle) run(PairKind::point_triangle, pair);
  for (const auto& pair : candidates.edge_edge) run(PairKind::edge_edge, pair);
}

double ContactPotential::energy(const Positions& x) const {
  double total = 0.0;
  for_each_active(x, false, [&](const ActivePair& pair) { total += pair.derivatives.value; });
  return total;
}

double ContactPotential::max_step(const Positions& x, const Positions& dx) const {
  if (!dx.allFinite() || !x.allFinite()) return 0.0;  // a NaN or infinite direction: no safe step
  const Positions end = x + dx;
  const CandidatePairs candidates = find_candidates(surface_, x, 0.0, &end);
  double step = 1.0;
  long budget = options_.ccd.max_total_iterations;  // evaluations left for this call
  auto run = [&](PairKind kind, const std::array<int, 2>& pair) {
    const std::array<int, 4> v = stencil(kind, pair);
    CcdOptions ccd = options_.ccd;
    ccd.max_iterations = std::min(ccd.max_iterations, budget);
    const CcdResult r = additive_ccd_linear_query(kind, points_of(x, v), points_of(end, v), step, ccd);
    budget -= r.iterations;
    step = std::min(step, r.step);
  };
  for (const auto& pair : candidates.point_triangle) run(PairKind::point_triangle, pair);
  for (const auto& pair : candidates.edge_edge) run(PairKind::edge_edge, pair);
  return step;
}

double ContactPotential::min_distance(const Positions& x, double range) const {
  const CandidatePairs candidates = find_candidates(surface_, x, range);
  double best = std::numeric_limits<double>::infinity();
  for (const auto& pair : candidates.point_triangle)
    best = std::min(
        best, pair_distance(PairKind::point_triangle, points_of(x, stencil(PairKind::point_triangle, pair))));
  for (const auto& pair : candidates.edge_edge)
    best =
        std::min(best, pair_distance(PairKind::edge_edge, points_of(x, stencil(PairKind::edge_edge, pair))));
  return best;
}

int ContactPotential::num_active(const Positions& x) const {
  int count = 0;
  for_each_active(x, false, [&](const ActivePair&) { ++count; });
  return count;
}

}  // namespace tailor::contact
