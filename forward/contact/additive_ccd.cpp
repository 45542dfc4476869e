// Additive CCD (Li et al. 2021, Codimensional IPC, Algorithm 1); see additive_ccd.hpp.
#include "forward/contact/additive_ccd.hpp"

#include <algorithm>
#include <cmath>

namespace tailor::contact {

double pair_distance(PairKind kind, const std::array<Point, 4>& points) {
  return std::sqrt(classify_pair(kind, points).squared_distance);
}

double additive_ccd(PairKind kind, const StencilPath& path, double rate_bound, double t_max,
                    const CcdOptions& options) {
  const double xi = options.min_separation, s = options.separation_fraction;
  std::array<Point, 4> points;
  path(0.0, points);
  auto gap = [&](const std::array<Point, 4>& x) {
    const double d = pair_distance(kind, x);
    return (d * d - xi * xi) / (d + xi);
  };
  const double gap0 = gap(points);
  if (!(gap0 > 0.0)) return 0.0;          // already in contact: no step is safe
  if (!(rate_bound > 0.0)) return t_max;  // no relative motion
  const double target = s * gap0;
  double t = 0.0;
  double advance = (1.0 - s) * gap0 / rate_bound;  // safe without a check: gap(advance) >= s gap0
  for (long iteration = 0; iteration < options.max_iterations; ++iteration) {
    const double next = t + advance;
    if (next >= t_max) return t_max;
    path(next, points);
    const double g = gap(points);
    if (iteration > 0 && g < target) return t;
    t = next;
    advance = 0.9 * g / rate_bound;
  }
  return t;  // budget exhausted: [0, t] is verified contact-free
}

double additive_ccd_linear(PairKind kind, const std::array<Point, 4>& start, const std::array<Point, 4>& end,
                           double t_max, const CcdOptions& options) {
  // Translating all four points together leaves the distance unchanged: remove the mean
  // displacement so that the rate bound is as small as possible.
  std::array<Point, 4> displacement;
  Point mean = Point::Zero();
  for (int k = 0; k < 4; ++k) {
    displacement[k] = end[k] - start[k];
    mean += 0.25 * displacement[k];
  }
  std::array<double, 4> length;
  for (int k = 0; k < 4; ++k) length[k] = (displacement[k] - mean).norm();
  const double rate = kind == PairKind::point_triangle
                          ? length[0] + std::max({length[1], length[2], length[3]})
                          : std::max(length[0], length[1]) + std::max(length[2], length[3]);
  const StencilPath path = [&](double t, std::array<Point, 4>& points) {
    for (int k = 0; k < 4; ++k) points[k] = start[k] + t * (displacement[k] - mean);
  };
  return additive_ccd(kind, path, rate, t_max, options);
}

}  // namespace tailor::contact
