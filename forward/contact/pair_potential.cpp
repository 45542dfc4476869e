// One contact pair's barrier with exact derivatives (see pair_potential.hpp).
#include "forward/contact/pair_potential.hpp"

#include "forward/contact/barrier.hpp"

namespace tailor::contact {

ClassifiedDistance classify_pair(PairKind kind, const std::array<Point, 4>& points) {
  return kind == PairKind::point_triangle
             ? classify_point_triangle(points[0], points[1], points[2], points[3])
             : classify_edge_edge(points[0], points[1], points[2], points[3]);
}

bool pair_barrier(PairKind kind, const std::array<Point, 4>& points, double s_hat, double mollifier_eps,
                  bool derivatives, PairDerivatives& out) {
  out = PairDerivatives{};
  out.distance = classify_pair(kind, points);
  if (out.distance.squared_distance >= s_hat) return false;
  const bool edge_pair = kind == PairKind::edge_edge;
  const double cross = edge_pair ? (points[1] - points[0]).cross(points[3] - points[2]).squaredNorm() : 0.0;
  out.mollified = edge_pair && cross < mollifier_eps;

  if (!derivatives) {
    const double s = branch_squared_distance(out.distance, stencil_values(points));
    out.value = barrier(s, s_hat).value;
    if (out.mollified) out.value *= edge_mollifier(cross, mollifier_eps).value;
    return true;
  }
  const auto jets = stencil_jets(points);
  const Dual2<12> s = branch_squared_distance(out.distance, jets);
  const ScalarDerivatives bs = barrier(s.v, s_hat);
  Dual2<12> energy = chain(s, bs.value, bs.first, bs.second);
  if (out.mollified) {
    const Dual2<12> c = edge_cross_squared(jets[0], jets[1], jets[2], jets[3]);
    const ScalarDerivatives m = edge_mollifier(c.v, mollifier_eps);
    energy = chain(c, m.value, m.first, m.second) * energy;
  }
  out.value = energy.v;
  out.gradient = energy.g;
  out.hessian = energy.h;
  return true;
}

}  // namespace tailor::contact
