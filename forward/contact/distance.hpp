#pragma once
// Squared unsigned distances between the primitives of IPC (Li et al. 2020, section 4.1 and
// supplement), with closest-feature classification. All distances here are SQUARED
// Euclidean distances [length^2] between world positions.
//
// A point-triangle or edge-edge pair is a stencil of four points (p, t0, t1, t2) or
// (a0, a1, b0, b1). Classification picks the closest features and hence one of four smooth
// formulas (a "branch"), evaluated on a subset of the stencil:
//   point_point    |p - q|^2
//   point_edge     |(e0 - p) x (e1 - p)|^2 / |e1 - e0|^2            (point to the edge's line)
//   point_plane    ((p - t0) . n)^2 / |n|^2,  n = (t1 - t0) x (t2 - t0)
//   line_line      ((b0 - a0) . n)^2 / |n|^2, n = (a1 - a0) x (b1 - b0)
// Each formula is a template on the scalar so that Dual2 (forward/core/dual2.hpp) gives its exact gradient
// and Hessian; within a branch the formula equals the true distance, so the derivatives of
// the classified distance are those of the branch formula.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <string>

#include "forward/core/dual2.hpp"

namespace tailor::contact {

enum class DistanceBranch { point_point, point_edge, point_plane, line_line };
std::string to_string(DistanceBranch branch);

// The branch and the stencil points it reads (indices 0..3 into the pair's four points;
// the first 2, 3, 4 or 4 entries are used).
struct ClassifiedDistance {
  DistanceBranch branch = DistanceBranch::point_point;
  std::array<int, 4> points{0, 1, 2, 3};
  double squared_distance = 0.0;
};

using Point = Eigen::Vector3d;

// Closest features of point p to triangle (t0, t1, t2); degenerate triangles fall back to
// their edges.
ClassifiedDistance classify_point_triangle(const Point& p, const Point& t0, const Point& t1, const Point& t2);
// Closest features of segments (a0, a1) and (b0, b1); (nearly) parallel segments fall back to
// the endpoint-to-segment distances, which are exact there.
ClassifiedDistance classify_edge_edge(const Point& a0, const Point& a1, const Point& b0, const Point& b1);
// Closest features of point p to segment (e0, e1), stencil (p, e0, e1) = (0, 1, 2).
ClassifiedDistance classify_point_edge(const Point& p, const Point& e0, const Point& e1);

// ---- The branch formulas, on any scalar (double or Dual2). ----
template <class S>
struct Vec3 {
  S x, y, z;
};
template <class S>
Vec3<S> operator-(const Vec3<S>& a, const Vec3<S>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class S>
S dot(const Vec3<S>& a, const Vec3<S>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class S>
Vec3<S> cross(const Vec3<S>& a, const Vec3<S>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

template <class S>
S point_point_squared(const Vec3<S>& p, const Vec3<S>& q) {
  const Vec3<S> d = p - q;
  return dot(d, d);
}
template <class S>
S point_edge_squared(const Vec3<S>& p, const Vec3<S>& e0, const Vec3<S>& e1) {
  const Vec3<S> c = cross(e0 - p, e1 - p);
  const Vec3<S> e = e1 - e0;
  return dot(c, c) / dot(e, e);
}
template <class S>
S point_plane_squared(const Vec3<S>& p, const Vec3<S>& t0, const Vec3<S>& t1, const Vec3<S>& t2) {
  const Vec3<S> n = cross(t1 - t0, t2 - t0);
  const S h = dot(p - t0, n);
  return h * h / dot(n, n);
}
template <class S>
S line_line_squared(const Vec3<S>& a0, const Vec3<S>& a1, const Vec3<S>& b0, const Vec3<S>& b1) {
  const Vec3<S> n = cross(a1 - a0, b1 - b0);
  const S h = dot(b0 - a0, n);
  return h * h / dot(n, n);
}
// |(a1 - a0) x (b1 - b0)|^2, the edge-edge mollifier's argument [length^4].
template <class S>
S edge_cross_squared(const Vec3<S>& a0, const Vec3<S>& a1, const Vec3<S>& b0, const Vec3<S>& b1) {
  const Vec3<S> n = cross(a1 - a0, b1 - b0);
  return dot(n, n);
}

// The branch formula on stencil points s[0..3] (only those in c.points are read).
template <class S>
S branch_squared_distance(const ClassifiedDistance& c, const std::array<Vec3<S>, 4>& s) {
  const auto& i = c.points;
  switch (c.branch) {
    case DistanceBranch::point_point:
      return point_point_squared(s[i[0]], s[i[1]]);
    case DistanceBranch::point_edge:
      return point_edge_squared(s[i[0]], s[i[1]], s[i[2]]);
    case DistanceBranch::point_plane:
      return point_plane_squared(s[i[0]], s[i[1]], s[i[2]], s[i[3]]);
    case DistanceBranch::line_line:
      return line_line_squared(s[i[0]], s[i[1]], s[i[2]], s[i[3]]);
  }
  return S(0.0);
}

// The four stencil points as jets in the 12 coordinates (point k, axis j -> input 3k + j).
std::array<Vec3<Dual2<12>>, 4> stencil_jets(const std::array<Point, 4>& points);
std::array<Vec3<double>, 4> stencil_values(const std::array<Point, 4>& points);

// Squared distance of the pair with its exact gradient and Hessian in the 12 coordinates.
Dual2<12> squared_distance_jet(const ClassifiedDistance& c, const std::array<Point, 4>& points);

}  // namespace tailor::contact
