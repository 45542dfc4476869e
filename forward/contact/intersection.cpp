// Edge-face intersection checks (see intersection.hpp).
#include "forward/contact/intersection.hpp"

namespace tailor::contact {
namespace {

// Six times the signed volume of (a, b, c, d).
double orient(const Point& a, const Point& b, const Point& c, const Point& d) {
  return (b - a).cross(c - a).dot(d - a);
}

}  // namespace

bool segment_intersects_triangle(const Point& a, const Point& b, const Point& t0, const Point& t1,
                                 const Point& t2) {
  const double sa = orient(t0, t1, t2, a), sb = orient(t0, t1, t2, b);
  if ((sa > 0 && sb > 0) || (sa < 0 && sb < 0)) return false;  // both on one side of the plane
  if (sa == 0 && sb == 0) {
    // Coplanar: touching counts when the segment comes within round-off of the triangle.
    return classify_point_triangle(a, t0, t1, t2).squared_distance == 0.0 ||
           classify_point_triangle(b, t0, t1, t2).squared_distance == 0.0;
  }
  // The line through a, b passes the triangle's edges on consistent sides.
  const double e0 = orient(a, b, t0, t1), e1 = orient(a, b, t1, t2), e2 = orient(a, b, t2, t0);
  return (e0 >= 0 && e1 >= 0 && e2 >= 0) || (e0 <= 0 && e1 <= 0 && e2 <= 0);
}

int count_edge_face_intersections(const ContactSurface& surface, const Positions& x) {
  // All (edge, face) pairs with a bounding-box rejection: O(edges x faces), for validation.
  int count = 0;
  auto p = [&](int v) -> Point { return x.row(v).transpose(); };
  for (int e = 0; e < surface.edges.rows(); ++e) {
    const int a = surface.edges(e, 0), b = surface.edges(e, 1);
    const Eigen::Vector3d lo = p(a).cwiseMin(p(b)), hi = p(a).cwiseMax(p(b));
    for (int f = 0; f < surface.faces.rows(); ++f) {
      const int f0 = surface.faces(f, 0), f1 = surface.faces(f, 1), f2 = surface.faces(f, 2);
      if (a == f0 || a == f1 || a == f2 || b == f0 || b == f1 || b == f2) continue;
      if (surface.grouped() && surface.group(a) == surface.group(f0) &&
          surface.group(b) == surface.group(f0) && surface.group(f1) == surface.group(f0) &&
          surface.group(f2) == surface.group(f0))
        continue;
      const Eigen::Vector3d flo = p(f0).cwiseMin(p(f1)).cwiseMin(p(f2)),
                            fhi = p(f0).cwiseMax(p(f1)).cwiseMax(p(f2));
      if ((hi.array() < flo.array()).any() || (fhi.array() < lo.array()).any()) continue;
      if (segment_intersects_triangle(p(a), p(b), p(f0), p(f1), p(f2))) ++count;
    }
  }
  return count;
}

}  // namespace tailor::contact
