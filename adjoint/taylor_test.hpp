#pragma once
// Taylor test of a reduced functional (public API; also the `tailor gradcheck` verb).
//
// Along a random direction dz (seeded), for h = h0, h0/2, ..., h0/2^halvings:
//   r0(h) = |J(z + h dz) - J(z)|                  falls as h   (rate ~1) unless dJ.dz = 0,
//   r1(h) = |J(z + h dz) - J(z) - h dJ.dz|        falls as h^2 (rate ~2) iff the gradient is right.
// A wrong gradient leaves r1 ~ h (rate ~1). Rows whose r1 is within 10x of the evaluation
// noise floor (round-off of J plus the forward solve's tolerance, estimated from J) carry no
// information about the rate: they are reported as "round-off", and a test whose informative
// rows are fewer than three does not pass. A vanishing directional derivative is reported,
// not passed.
#include <string>
#include <vector>

#include "adjoint/reduced_functional.hpp"

namespace tailor {

struct TaylorTestOptions {
  unsigned seed = 1;
  int halvings = 5;             // at least 4
  double initial_step = 1e-2;   // h0; the direction has entries u_i * max(|z_i|, direction_floor)
  double direction_floor = 1e-2;
  double min_rate = 1.9;        // on the second-order remainder
  // Absolute noise floor of J evaluations; 0 = estimate as 1e3 * eps * |J(z)|.
  double noise_floor = 0.0;
  Vector direction;             // optional: use this dz instead of a random one
};

struct TaylorRow {
  double step;
  double value;
  double remainder0, remainder1;
  double rate0, rate1;  // NaN for the first row and for rows next to round-off
  bool round_off;       // remainder1 is at the noise floor
};

enum class TaylorStatus { passed, failed, round_off, vanishing, evaluation_failed };
std::string to_string(TaylorStatus status);

struct TaylorTestResult {
  TaylorStatus status = TaylorStatus::failed;
  std::string message;
  double value = 0.0;                   // J(z)
  double directional_derivative = 0.0;  // dJ.dz
  double rate0 = 0.0, rate1 = 0.0;      // medians over informative rows
  Vector direction;
  std::vector<TaylorRow> rows;
  bool passed() const { return status == TaylorStatus::passed; }
  std::string table() const;
  std::string json() const;  // {"status", "rate0", "rate1", "rows": [...] , ...}
};

TaylorTestResult taylor_test(ReducedFunctional& functional, const Vector& z, const TaylorTestOptions& options = {});

// The same test one order up, for Hessian-vector products: with g the gradient,
//   r0(h) = ||g(z + h dz) - g(z)||,   r1(h) = ||g(z + h dz) - g(z) - h H dz||   (rate ~2).
// directional_derivative holds ||H dz||.
TaylorTestResult taylor_test_hessian(ReducedFunctional& functional, const Vector& z,
                                     const TaylorTestOptions& options = {});

}  // namespace tailor
