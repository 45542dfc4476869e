#pragma once
// Continuous collision detection by additive CCD (ACCD; Li, Kaufman, Jiang 2021,
// "Codimensional Incremental Potential Contact", Algorithm 1), conservative: it never
// reports a step that lets a pair touch (no false negatives), and it returns a step at which
// the gap is still at least a fraction of the initial one.
//
// For a pair whose points move along p_k(t), t in [0, t_max], with the rate bound
//   |d/dt (distance)| <= L   (for straight motion with displacements u_k, after removing
//   their mean: L = |u_p| + max_k |u_tk| (point-triangle) or max |u_a| + max |u_b| (edges)),
// the gap g(t) = (d^2 - xi^2) / (d + xi) (xi: minimum separation) can fall by at most L dt
// over dt. ACCD advances by dt = (1 - s) g0 / L, then by 0.9 g / L, re-measuring the exact
// distance after each advance, until t_max is passed or the gap falls below s g0. Every
// advance is smaller than the time the pair needs to close the current gap, so [0, t] is
// contact-free; the returned t leaves a gap >= s g0 > 0.
#include <array>
#include <functional>

#include "forward/contact/pair_potential.hpp"

namespace tailor::contact {

struct CcdOptions {
  double separation_fraction = 0.1;  // s: the returned step keeps gap >= s * initial gap
  double min_separation = 0.0;       // xi [length]: a thickness the pair must keep
  long max_iterations = 1000000;     // per query: an exhausted budget returns the (safe) step reached
  // Per max_step call over all its queries (ContactPotential::max_step,
  // rigid::ContactBodies::max_step): distance evaluations. Once spent, each remaining pair gets
  // only its first advance (1 - s) g0 / L, which needs no further check (one evaluation), so a
  // direction far longer than the gaps (e.g. from a nearly singular Newton step) costs at most
  // this much instead of max_iterations per pair.
  long max_total_iterations = 200000;
};

// How a query ended.
enum class CcdStatus {
  free,              // t_max reached: no contact possible on [0, t_max]
  separated,         // stopped where the gap would fall below s g0 (the step is < t_max)
  touching,          // the pair starts in contact (gap <= 0): step 0
  budget_exhausted,  // the iteration budget ended the query: the step reached, verified safe
  non_finite         // a NaN or infinite rate bound, t_max or position: refused, step 0
};
const char* to_string(CcdStatus status);

struct CcdResult {
  double step = 0.0;
  CcdStatus status = CcdStatus::free;
  long iterations = 0;  // distance evaluations after the first
};

// Stencil positions at time t.
using StencilPath = std::function<void(double t, std::array<Point, 4>& points)>;

// Largest safe time in [0, t_max] for a general (e.g. curved rigid) path with distance rate
// bound `rate_bound` [length per unit t]: t_max when no contact is possible, 0 when the pair
// starts in contact (gap <= 0).
double additive_ccd(PairKind kind, const StencilPath& path, double rate_bound, double t_max,
                    const CcdOptions& options = {});
// The same with how it ended; at most `max_iterations` evaluations after the first (default:
// options.max_iterations).
CcdResult additive_ccd_query(PairKind kind, const StencilPath& path, double rate_bound, double t_max,
                             const CcdOptions& options = {}, long max_iterations = -1);

// Straight motion from `start` to `end` (t in [0, 1] maps to start + t (end - start)).
double additive_ccd_linear(PairKind kind, const std::array<Point, 4>& start, const std::array<Point, 4>& end,
                           double t_max = 1.0, const CcdOptions& options = {});
CcdResult additive_ccd_linear_query(PairKind kind, const std::array<Point, 4>& start,
                                    const std::array<Point, 4>& end, double t_max = 1.0,
                                    const CcdOptions& options = {});

// Unsigned distance of a pair [length].
double pair_distance(PairKind kind, const std::array<Point, 4>& points);

}  // namespace tailor::contact
