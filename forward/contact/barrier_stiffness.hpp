#pragma once
// Adaptive barrier stiffness (Li et al. 2020, "Incremental Potential Contact", section 4.3 and
// its supplement; docs/methods.md section 13).
//
// Initial kappa: the value that best balances the barrier's gradient against the other forces
// at the start of a solve (a static solve, or a time step, where kappa only ever grows to it),
//   kappa = argmin_k |g_E + k g_B|^2 = -(g_E . g_B) / |g_B|^2,
// g_E the gradient of every other term and g_B that of the barrier at kappa = 1 (both over the
// free DOFs), clamped to [min_stiffness, max_stiffness]; without active pairs (g_B = 0),
// min_stiffness.
// Update: after every Newton iteration, when the smallest distance d is below
// distance_threshold and smaller than at the previous iteration, kappa is multiplied by
// `growth` (up to max_stiffness): the barrier stiffens only where pairs keep approaching.
#include <algorithm>
#include <cmath>

#include "forward/contact/barrier.hpp"
#include "forward/core/types.hpp"

namespace tailor::contact {

struct StiffnessOptions {
  bool adaptive = false;            // false: kappa stays ContactOptions::stiffness
  double min_stiffness = 0.0;       // [energy / length^4]; 0: ContactOptions::stiffness
  double max_stiffness = 0.0;       // 0: 100 x min_stiffness (IPC's ratio)
  double growth = 2.0;              // factor of each raise
  double distance_fraction = 1e-3;  // distance_threshold = fraction x d_hat
};

// -(g_E . g_B) / |g_B|^2 clamped to [lo, hi]; lo when g_B = 0 or the balance is negative.
inline double balanced_stiffness(const Vector& other_gradient, const Vector& barrier_gradient, double lo,
                                 double hi) {
  const double norm2 = barrier_gradient.squaredNorm();
  if (!(norm2 > 0.0)) return lo;
  const double kappa = -other_gradient.dot(barrier_gradient) / norm2;
  if (!std::isfinite(kappa)) return lo;
  return std::clamp(kappa, lo, hi);
}

// The kappa at which one pair at distance d_hat / 2 pushes with `force`: the pair force is
// -d(kappa b)/dd = kappa |b'(d^2)| 2 d (b on squared distances). A default minimum for adaptive
// kappa when no pair is active at the start.
inline double stiffness_for_force(double force, double d_hat) {
  const double d = 0.5 * d_hat;
  return force / (std::abs(barrier(d * d, d_hat * d_hat).first) * 2.0 * d);
}

// kappa * growth (at most hi) when the smallest distance is below the threshold and shrank
// since the previous iteration, kappa otherwise.
inline double raised_stiffness(double kappa, double previous_distance, double distance, double threshold,
                               double growth, double hi) {
  if (distance < threshold && distance < previous_distance) return std::min(hi, growth * kappa);
  return kappa;
}

}  // namespace tailor::contact
