#include "adjoint/taylor_test.hpp"

#include <algorithm>
#include <array>
#include <functional>
#include <cmath>
#include <iomanip>
#include <limits>
#include <random>
#include <sstream>

namespace tailor {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

std::string number(double v) {
  if (std::isnan(v)) return "null";
  std::ostringstream s;
  s << std::setprecision(17) << v;
  return s.str();
}

}  // namespace

std::string to_string(TaylorStatus status) {
  switch (status) {
    case TaylorStatus::passed: return "passed";
    case TaylorStatus::failed: return "failed";
    case TaylorStatus::round_off: return "round_off";
    case TaylorStatus::vanishing: return "vanishing";
    case TaylorStatus::evaluation_failed: return "evaluation_failed";
  }
  return "unknown";
}

namespace {

Vector random_direction(const Vector& z, const TaylorTestOptions& options) {
  if (options.direction.size() > 0) {
    if (options.direction.size() != z.size()) throw std::invalid_argument("taylor_test: direction has the wrong size");
    return options.direction;
  }
  std::mt19937 rng(options.seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vector dz(z.size());
  for (Eigen::Index i = 0; i < z.size(); ++i) dz[i] = u(rng) * std::max(std::abs(z[i]), options.direction_floor);
  return dz;
}

// Fills rows, rates and status from remainders(h) -> (value, r0, r1); `first_order_size` is
// |first-order term| at h0 and `noise` the evaluation noise floor of the remainders.
void tabulate(TaylorTestResult& result, const TaylorTestOptions& options, double first_order_size, double noise,
              const std::function<std::array<double, 3>(double)>& remainders) {
  const int halvings = std::max(options.halvings, 4);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  double h = options.initial_step;
  std::vector<double> rates0, rates1;
  for (int k = 0; k <= halvings; ++k, h *= 0.5) {
    const auto [value, r0, r1] = remainders(h);
    TaylorRow row{h, value, r0, r1, nan, nan, r1 <= 10.0 * noise};
    if (!result.rows.empty()) {
      const TaylorRow& prev = result.rows.back();
      if (row.remainder0 > 10.0 * noise && prev.remainder0 > 10.0 * noise) {
        row.rate0 = std::log2(prev.remainder0 / row.remainder0);
        rates0.push_back(row.rate0);
      }
      if (!row.round_off && !prev.round_off) {
        row.rate1 = std::log2(prev.remainder1 / row.remainder1);
        rates1.push_back(row.rate1);
      }
    }
    result.rows.push_back(row);
  }
  result.rate0 = median(rates0);
  result.rate1 = median(rates1);

  std::ostringstream msg;
  if (first_order_size <= 10.0 * noise) {
    result.status = TaylorStatus::vanishing;
    msg << "the directional derivative vanishes (first-order term " << first_order_size
        << " at h0 is at the noise floor): nothing was tested; choose another point or direction";
  } else if (rates1.size() < 3) {
    result.status = TaylorStatus::round_off;
    msg << "only " << rates1.size() << " rates above the noise floor " << noise
        << ": the second-order remainder is at round-off; increase initial_step or tighten the forward solve";
  } else if (result.rate1 >= options.min_rate) {
    result.status = TaylorStatus::passed;
    msg << "second-order remainder converges at rate " << std::fixed << std::setprecision(2) << result.rate1;
  } else {
    result.status = TaylorStatus::failed;
    msg << "second-order remainder converges at rate " << std::fixed << std::setprecision(2) << result.rate1 << " < "
        << options.min_rate << ": the derivative is wrong (or the functional is not smooth here)";
  }
  result.message = msg.str();
}

}  // namespace

TaylorTestResult taylor_test(ReducedFunctional& functional, const Vector& z, const TaylorTestOptions& options) {
  TaylorTestResult result;
  try {
    result.direction = random_direction(z, options);
    const Vector& dz = result.direction;
    Vector gradient;
    result.value = functional.value_and_gradient(z, gradient);
    result.directional_derivative = gradient.dot(dz);
    const double noise = options.noise_floor > 0.0
                             ? options.noise_floor
                             : 1e3 * std::numeric_limits<double>::epsilon() * std::max(std::abs(result.value), 1e-300);
    tabulate(result, options, std::abs(result.directional_derivative) * options.initial_step, noise, [&](double h) {
      const double value = functional.value(z + h * dz);
      return std::array<double, 3>{value, std::abs(value - result.value),
                                   std::abs(value - result.value - h * result.directional_derivative)};
    });
  } catch (const std::exception& e) {
    result.status = TaylorStatus::evaluation_failed;
    result.message = std::string("evaluation failed: ") + e.what();
  }
  return result;
}

TaylorTestResult taylor_test_hessian(ReducedFunctional& functional, const Vector& z, const TaylorTestOptions& options) {
  TaylorTestResult result;
  try {
    if (!functional.has_hessian_vector()) throw std::logic_error("the functional offers no Hessian-vector products");
    result.direction = random_direction(z, options);
    const Vector& dz = result.direction;
    Vector gradient;
    result.value = functional.value_and_gradient(z, gradient);
    const Vector hv = functional.hessian_vector(z, dz);
    result.directional_derivative = hv.norm();
    const double noise = options.noise_floor > 0.0
                             ? options.noise_floor
                             : 1e3 * std::numeric_limits<double>::epsilon() * std::max(gradient.norm(), 1e-300);
    tabulate(result, options, hv.norm() * options.initial_step, noise, [&](double h) {
      Vector g;
      const double value = functional.value_and_gradient(z + h * dz, g);
      return std::array<double, 3>{value, (g - gradient).norm(), (g - gradient - h * hv).norm()};
    });
  } catch (const std::exception& e) {
    result.status = TaylorStatus::evaluation_failed;
    result.message = std::string("evaluation failed: ") + e.what();
  }
  return result;
}

std::string TaylorTestResult::table() const {
  std::ostringstream s;
  s << "Taylor test: J = " << std::setprecision(10) << value << ", dJ.dz = " << directional_derivative << "\n";
  s << "        h          |J(z+h dz)-J(z)|   rate   |J(z+h dz)-J(z)-h dJ.dz|   rate\n";
  for (const auto& r : rows) {
    auto rate = [](double v) {
      std::ostringstream t;
      if (std::isnan(v))
        t << "   -";
      else
        t << std::fixed << std::setprecision(2) << std::setw(5) << v;
      return t.str();
    };
    s << "  " << std::scientific << std::setprecision(3) << std::setw(10) << r.step << "   " << std::setw(14)
      << r.remainder0 << "   " << rate(r.rate0) << "   " << std::setw(20) << r.remainder1 << "   " << rate(r.rate1)
      << (r.round_off ? "  (round-off)" : "") << "\n";
  }
  s << to_string(status) << ": " << message << "\n";
  return s.str();
}

std::string TaylorTestResult::json() const {
  std::ostringstream s;
  s << "{\n  \"status\": \"" << to_string(status) << "\",\n  \"message\": \"";
  for (char c : message) s << (c == '"' || c == '\\' ? std::string("\\") + c : std::string(1, c));
  s << "\",\n  \"value\": " << number(value) << ",\n  \"directional_derivative\": " << number(directional_derivative)
    << ",\n  \"rate0\": " << number(rate0) << ",\n  \"rate1\": " << number(rate1) << ",\n  \"rows\": [\n";
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const auto& r = rows[k];
    s << "    {\"step\": " << number(r.step) << ", \"value\": " << number(r.value) << ", \"remainder0\": "
      << number(r.remainder0) << ", \"remainder1\": " << number(r.remainder1) << ", \"rate0\": " << number(r.rate0)
      << ", \"rate1\": " << number(r.rate1) << ", \"round_off\": " << (r.round_off ? "true" : "false") << "}"
      << (k + 1 < rows.size() ? "," : "") << "\n";
  }
  s << "  ]\n}\n";
  return s.str();
}

}  // namespace tailor
