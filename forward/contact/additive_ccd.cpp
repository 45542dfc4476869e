// Additive CCD (Li et al. 2021, Codimensional IPC, Algorithm 1); see additive_ccd.hpp.
#include "forward/contact/additive_ccd.hpp"

#include <algorithm>
#include <cmath>

namespace tailor::contact {

double pair_distance(PairKind kind, const std::array<Point, 4>& points) {
  return std::sqrt(classify_pair(kind, points).squared_distance);
}

const char* to_string(CcdStatus status) {
  switch (status) {
    case CcdStatus::free:
      return "free";
    case CcdStatus::separated:
      return "separated";
    case CcdStatus::touching:
      return "touching";
    case CcdStatus::budget_exhausted:
      return "budget_exhausted";
    case CcdStatus::non_finite:
      return "non_finite";
  }
  return "unknown";
}

CcdResult additive_ccd_query(PairKind kind, const StencilPath& path, double rate_bound, double t_max,
                             const CcdOptions& options, long max_iterations) {
  if (max_iterations < 0) max_iterations = options.max_iterations;
  const double xi = options.min_separation, s = options.separation_fraction;
  CcdResult result;
  // A NaN or infinite motion has no safe step; a NaN would also never end the loop below by
  // its comparisons.
  if (std::isnan(rate_bound) || !std::isfinite(t_max)) {
    result.status = CcdStatus::non_finite;
    return result;
  }
  std::array<Point, 4> points;
  path(0.0, points);
  auto gap = [&](const std::array<Point, 4>& x) {
    const double d = pair_distance(kind, x);
    return (d * d - xi * xi) / (d + xi);
  };
  const double gap0 = gap(points);
  if (std::isnan(gap0) || !std::isfinite(rate_bound)) {
    result.status = CcdStatus::non_finite;
    return result;
  }
  if (!(gap0 > 0.0)) {  // already in contact: no step is safe
    result.status = CcdStatus::touching;
    return result;
  }
  result.step = t_max;
  if (!(rate_bound > 0.0)) return result;  // no relative motion
  const double target = s * gap0;
  double t = 0.0;
  double advance = (1.0 - s) * gap0 / rate_bound;  // safe without a check: gap(advance) >= s gap0
  for (long iteration = 0;; ++iteration) {
    const double next = t + advance;
    if (next >= t_max) return result;
    if (iteration >= max_iterations) {
      // Budget exhausted: [0, t] is verified contact-free (at iteration 0, [0, advance] is,
      // by the rate bound alone).
      result.step = iteration == 0 ? advance : t;
      result.status = CcdStatus::budget_exhausted;
      return result;
    }
    path(next, points);
    const double g = gap(points);
    result.iterations = iteration + 1;
    if (std::isnan(g)) {
      result.step = 0.0;
      result.status = CcdStatus::non_finite;
      return result;
    }
    if (iteration > 0 && g < target) {
      result.step = t;
      result.status = CcdStatus::separated;
      return result;
    }
    t = next;
    advance = 0.9 * g / rate_bound;
  }
}

double additive_ccd(PairKind kind, const StencilPath& path, double rate_bound, double t_max,
                    const CcdOptions& options) {
  return additive_ccd_query(kind, path, rate_bound, t_max, options).step;
}

double additive_ccd_linear(PairKind kind, const std::array<Point, 4>& start, const std::array<Point, 4>& end,
                           double t_max, const CcdOptions& options) {
  return additive_ccd_linear_query(kind, start, end, t_max, options).step;
}

CcdResult additive_ccd_linear_query(PairKind kind, const std::array<Point, 4>& start,
                                    const std::array<Point, 4>& end, double t_max, const CcdOptions& options) {
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
  return additive_ccd_query(kind, path, rate, t_max, options);
}

}  // namespace tailor::contact
