#pragma once
// Broad phase: candidate point-triangle and edge-edge pairs of a ContactSurface whose
// axis-aligned bounding boxes, inflated by half the activation distance each, overlap
// (sweep and prune along the axis of largest spread). Cost O(n log n + k), k the number of
// box pairs overlapping along that axis. Every pair at distance < inflation is a candidate:
// a box contains its primitive, and the distance between two boxes never exceeds that of
// the primitives they hold.
//
// With end positions, each box covers the primitive at both ends of the linear motion (and
// hence, by convexity, along the whole motion): the candidates of continuous collision
// detection. `motion_bound` (per vertex, optional) inflates a vertex's box further: a bound
// on how far a curved (rigid) trajectory strays from the straight one.
#include <array>
#include <vector>

#include "forward/contact/contact_surface.hpp"

namespace tailor::contact {

struct CandidatePairs {
  std::vector<std::array<int, 2>> point_triangle;  // (vertex, face)
  std::vector<std::array<int, 2>> edge_edge;       // (edge a, edge b), a < b
  std::size_t size() const { return point_triangle.size() + edge_edge.size(); }
};

// Positions in [length]; `inflation` >= 0 [length] (the activation distance d_hat).
// Throws std::invalid_argument when the position rows do not match the surface.
CandidatePairs find_candidates(const ContactSurface& surface, const Positions& start, double inflation,
                               const Positions* end = nullptr, const Eigen::VectorXd* motion_bound = nullptr);

// The same pairs by testing all of them (for tests and tiny surfaces): those whose
// classified distance at `positions` is below `distance`.
CandidatePairs brute_force_pairs(const ContactSurface& surface, const Positions& positions, double distance);

// The filters shared by both: a vertex and its own face, edges sharing a vertex, and
// primitives that lie in one group are never pairs.
bool admissible_point_triangle(const ContactSurface& surface, int vertex, int face);
bool admissible_edge_edge(const ContactSurface& surface, int edge_a, int edge_b);

}  // namespace tailor::contact
