#pragma once
// The IPC log barrier and the edge-edge mollifier (Li et al. 2020, eqs. 6 and 10), as scalar
// functions with their first and second derivatives.
//
// tailor's barrier acts on SQUARED distances: s = d^2 [length^2], s_hat = d_hat^2,
//   b(s) = -(s - s_hat)^2 ln(s / s_hat)   for 0 < s < s_hat,   0 for s >= s_hat,
// C^2 at s_hat (b, b' and b'' all tend to 0 there), +infinity for s <= 0 (an intersection).
#include <cmath>
#include <limits>

namespace tailor::contact {

struct ScalarDerivatives {
  double value = 0.0;
  double first = 0.0;   // d/ds
  double second = 0.0;  // d2/ds2
};

// b(s), b'(s), b''(s) for squared distance s and squared activation distance s_hat.
inline ScalarDerivatives barrier(double s, double s_hat) {
  ScalarDerivatives r;
  if (s >= s_hat) return r;
  if (s <= 0.0) {
    r.value = std::numeric_limits<double>::infinity();
    return r;
  }
  const double diff = s - s_hat, log_ratio = std::log(s / s_hat);
  r.value = -diff * diff * log_ratio;
  r.first = -2.0 * diff * log_ratio - diff * diff / s;
  r.second = -2.0 * log_ratio - 4.0 * diff / s + diff * diff / (s * s);
  return r;
}

// Edge-edge mollifier m(c) = (2 - c / eps) c / eps for c < eps, 1 otherwise (C^1 at eps), with
// c = |(a1 - a0) x (b1 - b0)|^2 [length^4] and eps = 1e-3 |A|^2 |B|^2 from the rest lengths.
inline ScalarDerivatives edge_mollifier(double c, double eps) {
  ScalarDerivatives r;
  if (c >= eps) {
    r.value = 1.0;
    return r;
  }
  const double q = c / eps;
  r.value = (2.0 - q) * q;
  r.first = (2.0 - 2.0 * q) / eps;
  r.second = -2.0 / (eps * eps);
  return r;
}

// The mollifier threshold of an edge pair from its rest edge vectors' squared lengths.
inline double mollifier_threshold(double rest_length_a_squared, double rest_length_b_squared) {
  return 1e-3 * rest_length_a_squared * rest_length_b_squared;
}

}  // namespace tailor::contact
