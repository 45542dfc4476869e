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
  long max_iterations = 1000000;     // an exhausted budget returns the (safe) step reached
};

// Stencil positions at time t.
using StencilPath = std::function<void(double t, std::array<Point, 4>& points)>;

// Largest safe time in [0, t_max] for a general (e.g. curved rigid) path with distance rate
// bound `rate_bound` [length per unit t]: t_max when no contact is possible, 0 when the pair
// starts in contact (gap <= 0).
double additive_ccd(PairKind kind, const StencilPath& path, double rate_bound, double t_max,
                    const CcdOptions& options = {});

// Straight motion from `start` to `end` (t in [0, 1] maps to start + t (end - start)).
double additive_ccd_linear(PairKind kind, const std::array<Point, 4>& start, const std::array<Point, 4>& end,
                           double t_max = 1.0, const CcdOptions& options = {});

// Unsigned distance of a pair [length].
double pair_distance(PairKind kind, const std::array<Point, 4>& points);

}  // namespace tailor::contact
