#pragma once
// Intersection checks for contact surfaces (validation of IPC's intersection-free guarantee;
// distances alone miss an edge piercing a face interior). Two closed triangle surfaces
// intersect iff an edge of one crosses a face of the other (or one lies inside the other,
// which is not detected here). The segment-triangle test uses the signs of orientation
// determinants in double precision (not exact predicates): touching within round-off counts
// as crossing.
#include "forward/contact/broad_phase.hpp"
#include "forward/contact/distance.hpp"

namespace tailor::contact {

// True when segment (a, b) meets triangle (t0, t1, t2) (closed sets, non-degenerate triangle).
bool segment_intersects_triangle(const Point& a, const Point& b, const Point& t0, const Point& t1,
                                 const Point& t2);

// The number of (edge, face) pairs of `surface` at `positions` that cross, over pairs sharing
// no vertex and not within one group (all pairs with a box rejection: for validation).
int count_edge_face_intersections(const ContactSurface& surface, const Positions& positions);

}  // namespace tailor::contact
