#pragma once
// Derivative checks shared by the parameterization tests: every map is checked the same way.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "adjoint/derivative_check.hpp"
#include "adjoint/parameterization.hpp"

namespace tailor::testing {

inline Vector random_vector(Eigen::Index n, unsigned seed, double lo = -1.0, double hi = 1.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  Vector v(n);
  for (Eigen::Index i = 0; i < n; ++i) v[i] = u(rng);
  return v;
}

// (dp/dz) dz against central differences of apply along dz.
inline DerivativeCheck check_jacobian(const Parameterization& map, const Vector& z, unsigned seed = 7) {
  const Vector dz = random_vector(map.num_design(), seed);
  return check_directional_derivative(map.name() + " jacobian_times",
                                      [&](double t) { return map.apply(z + t * dz); },
                                      map.jacobian_times(z, dz), {});
}

// sum_i w_i d2p_i/dz2 dz against central differences of z -> (dp/dz)^T w along dz.
inline DerivativeCheck check_second_derivative(const Parameterization& map, const Vector& z,
                                               unsigned seed = 11) {
  const Vector w = random_vector(map.num_params(), seed);
  const Vector dz = random_vector(map.num_design(), seed + 1);
  return check_directional_derivative(map.name() + " second_derivative_times",
                                      [&](double t) { return map.jacobian_transpose_times(z + t * dz, w); },
                                      map.second_derivative_times(z, w, dz), {});
}

// |w.(J dz) - (J^T w).dz| relative to the magnitudes of the two sums' terms (a plain
// |w.(J dz)| could vanish by cancellation while both products are large).
inline double dot_product_mismatch(const Parameterization& map, const Vector& z, unsigned seed = 3) {
  const Vector dz = random_vector(map.num_design(), seed);
  const Vector w = random_vector(map.num_params(), seed + 1);
  const Vector Jdz = map.jacobian_times(z, dz);
  const Vector JTw = map.jacobian_transpose_times(z, w);
  const double scale = (w.cwiseAbs().dot(Jdz.cwiseAbs()) + JTw.cwiseAbs().dot(dz.cwiseAbs()));
  return std::abs(w.dot(Jdz) - JTw.dot(dz)) / std::max(scale, std::numeric_limits<double>::min());
}

// All first-order checks for any map.
inline void expect_first_order_consistent(const Parameterization& map, const Vector& z, bool nonlinear) {
  SCOPED_TRACE(map.name());
  const DerivativeCheck c = check_jacobian(map, z);
  EXPECT_TRUE(c.passed) << c.message;
  if (nonlinear) {
    EXPECT_NEAR(c.observed_order, 2.0, 0.25) << c.message;
  }
  EXPECT_LT(dot_product_mismatch(map, z), 1e-12);
}

// Second order for a nonlinear map: differences of J^T w converge to the analytic product.
inline void expect_second_order_consistent(const Parameterization& map, const Vector& z) {
  SCOPED_TRACE(map.name());
  const DerivativeCheck c = check_second_derivative(map, z);
  EXPECT_TRUE(c.passed) << c.message;
  EXPECT_NEAR(c.observed_order, 2.0, 0.25) << c.message;
}

// Second order for a linear map: the analytic term is exactly zero and J^T w does not move,
// which the checker reports as "vanishing" (never as passed).
inline void expect_linear_in_z(const Parameterization& map, const Vector& z) {
  SCOPED_TRACE(map.name());
  const Vector w = random_vector(map.num_params(), 5), dz = random_vector(map.num_design(), 6);
  EXPECT_EQ(map.second_derivative_times(z, w, dz), Vector::Zero(map.num_design()));
  const DerivativeCheck c = check_second_derivative(map, z);
  EXPECT_TRUE(c.vanishing) << c.message;
}

// Expects std::invalid_argument whose message contains every fragment.
inline void expect_invalid(const std::function<void()>& call, const std::vector<std::string>& fragments) {
  try {
    call();
    ADD_FAILURE() << "expected std::invalid_argument mentioning '" << fragments.front() << "'";
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    for (const auto& f : fragments)
      EXPECT_NE(message.find(f), std::string::npos) << "'" << f << "' not in: " << message;
  }
}

}  // namespace tailor::testing
