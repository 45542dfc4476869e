#pragma once
// Taylor test of a reduced functional (public API; also the `tailor gradcheck` verb).
//
// Along a random direction dz (seeded), with the first-order term t(h) = h |dJ.dz|:
//   r0(h) = |J(z + h dz) - J(z)|                  falls as h   (rate ~1) unless dJ.dz = 0,
//   r1(h) = |J(z + h dz) - J(z) - h dJ.dz|        falls as h^2 (rate ~2) iff the gradient is right.
// A rate of 2 only means something in the asymptotic regime, where the first-order term
// dominates: with too large a step the second-order term dominates r0 too, and a gradient off
// by 50% passes (r1 then falls at rate 2 because h^2 dominates it as well). So the test first
// finds its step:
//  1. search: from h = initial_step, shrink h while r1 > asymptotic_fraction * t(h) (jumping
//     by the factor that r1 / t ~ h predicts), and grow it while r1 is too close to the
//     evaluation noise floor (round-off of J plus the forward solve's tolerance) for the
//     halvings to resolve a rate;
//  2. judge: from the step found, `halvings` halvings; it passes when the first-order rate is
//     near 1 (first_rate_tolerance) and the median second-order rate over at least three rows
//     above the noise floor is >= min_rate.
// Statuses: passed; failed (a rate below min_rate, or a remainder that stays a fixed fraction
// of the first-order term as h shrinks: the derivative is wrong); not_asymptotic (no step
// satisfies both the asymptotic and the noise condition: say which); round_off (the remainder
// is at the noise floor at every step tried, e.g. a functional linear in z); vanishing
// (dJ.dz = 0: nothing tested); evaluation_failed. Every evaluated row is reported; the judged
// ones have `judged` set.
#include <string>
#include <vector>

#include "adjoint/reduced_functional.hpp"

namespace tailor {

struct TaylorTestOptions {
  unsigned seed = 1;
  int halvings = 5;  // at least 4, in the judged rows
  double initial_step =
      1e-2;  // where the search starts; the direction has entries u_i * max(|z_i|, direction_floor)
  double direction_floor = 1e-2;
  double min_rate = 1.9;              // on the second-order remainder
  double asymptotic_fraction = 0.1;   // r1 <= this * t(h) at the judged step
  double first_rate_tolerance = 0.1;  // |median first-order rate - 1| allowed
  int max_search_steps = 12;          // evaluations spent on finding the step
  // Absolute noise floor of J evaluations; 0 = estimate as 1e3 * eps * |J(z)|.
  double noise_floor = 0.0;
  Vector direction;  // optional: use this dz instead of a random one
};

struct TaylorRow {
  double step;
  double value;
  double remainder0, remainder1;
  double rate0, rate1;  // NaN for the first row and for rows next to round-off
  bool round_off;       // remainder1 is at the noise floor
  double noise;         // the noise floor of this row's remainders
  bool judged;          // one of the rows the verdict rests on (false: a search row)
};

enum class TaylorStatus { passed, failed, not_asymptotic, round_off, vanishing, evaluation_failed };
std::string to_string(TaylorStatus status);

struct TaylorTestResult {
  TaylorStatus status = TaylorStatus::failed;
  std::string message;
  double value = 0.0;                   // J(z)
  double directional_derivative = 0.0;  // dJ.dz
  double rate0 = 0.0, rate1 = 0.0;      // medians over the judged informative rows
  double step = 0.0;                    // the step the search settled on (0 if none)
  Vector direction;
  std::vector<TaylorRow> rows;
  bool passed() const { return status == TaylorStatus::passed; }
  std::string table() const;
};

TaylorTestResult taylor_test(ReducedFunctional& functional, const Vector& z,
                             const TaylorTestOptions& options = {});

// The same test one order up, for Hessian-vector products: with g the gradient,
//   r0(h) = ||g(z + h dz) - g(z)||,   r1(h) = ||g(z + h dz) - g(z) - h H dz||   (rate ~2).
// directional_derivative holds ||H dz||.
TaylorTestResult taylor_test_hessian(ReducedFunctional& functional, const Vector& z,
                                     const TaylorTestOptions& options = {});

}  // namespace tailor
