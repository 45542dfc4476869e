// Sweep-and-prune broad phase (see broad_phase.hpp).
#include "forward/contact/broad_phase.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

#include "forward/contact/distance.hpp"

namespace tailor::contact {
namespace {

struct Box {
  Eigen::Vector3d lo, hi;
  bool overlaps(const Box& o) const {
    return (lo.array() <= o.hi.array()).all() && (o.lo.array() <= hi.array()).all();
  }
};

Box merge(const Box& a, const Box& b) { return {a.lo.cwiseMin(b.lo), a.hi.cwiseMax(b.hi)}; }

// Box pairs (i in a, j in b) that overlap; with `self`, a == b and only i < j.
template <class Visit>
void sweep(const std::vector<Box>& a, const std::vector<Box>& b, bool self, int axis, Visit&& visit) {
  struct Event {
    double lo;
    int index;
    bool from_a;
  };
  std::vector<Event> events;
  events.reserve(a.size() + (self ? 0 : b.size()));
  for (std::size_t i = 0; i < a.size(); ++i) events.push_back({a[i].lo[axis], static_cast<int>(i), true});
  if (!self)
    for (std::size_t j = 0; j < b.size(); ++j) events.push_back({b[j].lo[axis], static_cast<int>(j), false});
  std::sort(events.begin(), events.end(), [](const Event& x, const Event& y) { return x.lo < y.lo; });
  std::vector<int> active_a, active_b;
  auto prune = [&](std::vector<int>& active, const std::vector<Box>& boxes, double lo) {
    std::size_t kept = 0;
    for (int k : active)
      if (boxes[static_cast<std::size_t>(k)].hi[axis] >= lo) active[kept++] = k;
    active.resize(kept);
  };
  for (const Event& e : events) {
    if (self) {
      prune(active_a, a, e.lo);
      const Box& box = a[static_cast<std::size_t>(e.index)];
      for (int k : active_a)
        if (box.overlaps(a[static_cast<std::size_t>(k)])) visit(std::min(k, e.index), std::max(k, e.index));
      active_a.push_back(e.index);
    } else if (e.from_a) {
      prune(active_b, b, e.lo);
      const Box& box = a[static_cast<std::size_t>(e.index)];
      for (int k : active_b)
        if (box.overlaps(b[static_cast<std::size_t>(k)])) visit(e.index, k);
      active_a.push_back(e.index);
    } else {
      prune(active_a, a, e.lo);
      const Box& box = b[static_cast<std::size_t>(e.index)];
      for (int k : active_a)
        if (box.overlaps(a[static_cast<std::size_t>(k)])) visit(k, e.index);
      active_b.push_back(e.index);
    }
  }
}

}  // namespace

bool admissible_point_triangle(const ContactSurface& surface, int vertex, int face) {
  const auto f = surface.faces.row(face);
  if (vertex == f[0] || vertex == f[1] || vertex == f[2]) return false;
  if (!surface.grouped()) return true;
  const int g = surface.group(vertex);
  return !(surface.group(f[0]) == g && surface.group(f[1]) == g && surface.group(f[2]) == g);
}

bool admissible_edge_edge(const ContactSurface& surface, int edge_a, int edge_b) {
  const auto a = surface.edges.row(edge_a), b = surface.edges.row(edge_b);
  if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1]) return false;
  if (!surface.grouped()) return true;
  const int g = surface.group(a[0]);
  return !(surface.group(a[1]) == g && surface.group(b[0]) == g && surface.group(b[1]) == g);
}

CandidatePairs find_candidates(const ContactSurface& surface, const Positions& start, double inflation,
                               const Positions* end, const Eigen::VectorXd* motion_bound) {
  const int n = surface.num_vertices;
  if (start.rows() != n || (end && end->rows() != n) || (motion_bound && motion_bound->size() != n))
    throw std::invalid_argument("find_candidates: positions for " + std::to_string(start.rows()) +
                                " vertices, the surface has " + std::to_string(n));
  if (!(inflation >= 0.0)) throw std::invalid_argument("find_candidates: inflation must be >= 0");
  std::vector<Box> vertex_boxes(static_cast<std::size_t>(n));
  for (int v = 0; v < n; ++v) {
    Box box{start.row(v).transpose(), start.row(v).transpose()};
    if (end) box = merge(box, Box{end->row(v).transpose(), end->row(v).transpose()});
    const double pad = 0.5 * inflation + (motion_bound ? (*motion_bound)[v] : 0.0);
    box.lo.array() -= pad;
    box.hi.array() += pad;
    vertex_boxes[static_cast<std::size_t>(v)] = box;
  }
  auto vbox = [&](int v) -> const Box& { return vertex_boxes[static_cast<std::size_t>(v)]; };
  std::vector<Box> edge_boxes(static_cast<std::size_t>(surface.edges.rows()));
  for (int e = 0; e < surface.edges.rows(); ++e)
    edge_boxes[static_cast<std::size_t>(e)] = merge(vbox(surface.edges(e, 0)), vbox(surface.edges(e, 1)));
  std::vector<Box> face_boxes(static_cast<std::size_t>(surface.faces.rows()));
  for (int f = 0; f < surface.faces.rows(); ++f)
    face_boxes[static_cast<std::size_t>(f)] =
        merge(merge(vbox(surface.faces(f, 0)), vbox(surface.faces(f, 1))), vbox(surface.faces(f, 2)));

  // Sweep along the axis of largest spread of the vertices.
  int axis = 0;
  if (n > 0) {
    const Eigen::Vector3d spread = start.colwise().maxCoeff() - start.colwise().minCoeff();
    spread.maxCoeff(&axis);
  }
  CandidatePairs pairs;
  sweep(vertex_boxes, face_boxes, false, axis, [&](int v, int f) {
    if (admissible_point_triangle(surface, v, f)) pairs.point_triangle.push_back({v, f});
  });
  sweep(edge_boxes, edge_boxes, true, axis, [&](int a, int b) {
    if (admissible_edge_edge(surface, a, b)) pairs.edge_edge.push_back({a, b});
  });
  std::sort(pairs.point_triangle.begin(), pairs.point_triangle.end());
  std::sort(pairs.edge_edge.begin(), pairs.edge_edge.end());
  return pairs;
}

CandidatePairs brute_force_pairs(const ContactSurface& surface, const Positions& x, double distance) {
  CandidatePairs pairs;
  const double s = distance * distance;
  auto p = [&](int v) -> Point { return x.row(v).transpose(); };
  for (int v = 0; v < surface.num_vertices; ++v)
    for (int f = 0; f < surface.faces.rows(); ++f)
      if (admissible_point_triangle(surface, v, f) &&
          classify_point_triangle(p(v), p(surface.faces(f, 0)), p(surface.faces(f, 1)),
                                  p(surface.faces(f, 2)))
                  .squared_distance < s)
        pairs.point_triangle.push_back({v, f});
  for (int a = 0; a < surface.edges.rows(); ++a)
    for (int b = a + 1; b < surface.edges.rows(); ++b)
      if (admissible_edge_edge(surface, a, b) &&
          classify_edge_edge(p(surface.edges(a, 0)), p(surface.edges(a, 1)), p(surface.edges(b, 0)),
                             p(surface.edges(b, 1)))
                  .squared_distance < s)
        pairs.edge_edge.push_back({a, b});
  return pairs;
}

}  // namespace tailor::contact
