// Closest-feature classification of the IPC distances (see distance.hpp).
#include "forward/contact/distance.hpp"

namespace tailor::contact {

std::string to_string(DistanceBranch branch) {
  switch (branch) {
    case DistanceBranch::point_point:
      return "point_point";
    case DistanceBranch::point_edge:
      return "point_edge";
    case DistanceBranch::point_plane:
      return "point_plane";
    case DistanceBranch::line_line:
      return "line_line";
  }
  return "unknown";
}

ClassifiedDistance classify_point_edge(const Point& p, const Point& e0, const Point& e1) {
  ClassifiedDistance c;
  const Point e = e1 - e0;
  const double length_squared = e.squaredNorm();
  const double t = length_squared > 0.0 ? (p - e0).dot(e) / length_squared : 0.0;
  if (t <= 0.0) {
    c.branch = DistanceBranch::point_point;
    c.points = {0, 1, 1, 1};
    c.squared_distance = (p - e0).squaredNorm();
  } else if (t >= 1.0) {
    c.branch = DistanceBranch::point_point;
    c.points = {0, 2, 2, 2};
    c.squared_distance = (p - e1).squaredNorm();
  } else {
    c.branch = DistanceBranch::point_edge;
    c.points = {0, 1, 2, 2};
    c.squared_distance = (p - (e0 + t * e)).squaredNorm();
  }
  return c;
}

namespace {

// Classifies point `point` against edge (`first`, `second`) of a four-point stencil.
ClassifiedDistance point_edge_in_stencil(const std::array<Point, 4>& s, int point, int first, int second) {
  ClassifiedDistance c = classify_point_edge(s[point], s[first], s[second]);
  const std::array<int, 3> map{point, first, second};
  for (int& i : c.points) i = map[i];
  return c;
}

ClassifiedDistance closest_of(std::initializer_list<ClassifiedDistance> candidates) {
  ClassifiedDistance best = *candidates.begin();
  for (const ClassifiedDistance& c : candidates)
    if (c.squared_distance < best.squared_distance) best = c;
  return best;
}

}  // namespace

ClassifiedDistance classify_point_triangle(const Point& p, const Point& t0, const Point& t1,
                                           const Point& t2) {
  const std::array<Point, 4> s{p, t0, t1, t2};
  const Point n = (t1 - t0).cross(t2 - t0);
  if (n.squaredNorm() > 0.0) {
    // The projection of p lies inside when p is on the inner side of all three edges.
    const bool inside = (t1 - t0).cross(p - t0).dot(n) >= 0.0 && (t2 - t1).cross(p - t1).dot(n) >= 0.0 &&
                        (t0 - t2).cross(p - t2).dot(n) >= 0.0;
    if (inside) {
      ClassifiedDistance c;
      c.branch = DistanceBranch::point_plane;
      c.points = {0, 1, 2, 3};
      const double h = (p - t0).dot(n);
      c.squared_distance = h * h / n.squaredNorm();
      return c;
    }
  }
  return closest_of({point_edge_in_stencil(s, 0, 1, 2), point_edge_in_stencil(s, 0, 2, 3),
                     point_edge_in_stencil(s, 0, 3, 1)});
}

ClassifiedDistance classify_edge_edge(const Point& a0, const Point& a1, const Point& b0, const Point& b1) {
  const std::array<Point, 4> s{a0, a1, b0, b1};
  const Point u = a1 - a0, v = b1 - b0, w = a0 - b0;
  const double a = u.squaredNorm(), b = u.dot(v), c = v.squaredNorm(), d = u.dot(w), e = v.dot(w);
  const double denominator = a * c - b * b;  // = |u x v|^2
  // Interior closest points of the two lines; below this relative threshold the lines are
  // parallel to round-off and the endpoint distances below are exact (or as close).
  if (denominator > 1e-12 * a * c) {
    const double sa = (b * e - c * d) / denominator, tb = (a * e - b * d) / denominator;
    if (sa > 0.0 && sa < 1.0 && tb > 0.0 && tb < 1.0) {
      ClassifiedDistance r;
      r.branch = DistanceBranch::line_line;
      r.points = {0, 1, 2, 3};
      r.squared_distance = (w + sa * u - tb * v).squaredNorm();
      return r;
    }
  }
  return closest_of({point_edge_in_stencil(s, 0, 2, 3), point_edge_in_stencil(s, 1, 2, 3),
                     point_edge_in_stencil(s, 2, 0, 1), point_edge_in_stencil(s, 3, 0, 1)});
}

std::array<Vec3<Dual2<12>>, 4> stencil_jets(const std::array<Point, 4>& points) {
  std::array<Vec3<Dual2<12>>, 4> s;
  for (int k = 0; k < 4; ++k) {
    s[k].x = Dual2<12>::variable(points[k].x(), 3 * k);
    s[k].y = Dual2<12>::variable(points[k].y(), 3 * k + 1);
    s[k].z = Dual2<12>::variable(points[k].z(), 3 * k + 2);
  }
  return s;
}

std::array<Vec3<double>, 4> stencil_values(const std::array<Point, 4>& points) {
  std::array<Vec3<double>, 4> s;
  for (int k = 0; k < 4; ++k) s[k] = {points[k].x(), points[k].y(), points[k].z()};
  return s;
}

Dual2<12> squared_distance_jet(const ClassifiedDistance& c, const std::array<Point, 4>& points) {
  return branch_squared_distance(c, stencil_jets(points));
}

}  // namespace tailor::contact
