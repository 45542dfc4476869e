#include "adjoint/taylor_test.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iomanip>
#include <limits>
#include <random>
#include <sstream>

#include "forward/core/statistics.hpp"

namespace tailor {
std::string to_string(TaylorStatus status) {
  switch (status) {
    case TaylorStatus::passed:
      return "passed";
    case TaylorStatus::failed:
      return "failed";
    case TaylorStatus::not_asymptotic:
      return "not_asymptotic";
    case TaylorStatus::round_off:
      return "round_off";
    case TaylorStatus::vanishing:
      return "vanishing";
    case TaylorStatus::evaluation_failed:
      return "evaluation_failed";
  }
  return "unknown";
}

namespace {

Vector random_direction(const Vector& z, const TaylorTestOptions& options) {
  if (options.direction.size() > 0) {
    if (options.direction.size() != z.size())
      throw std::invalid_argument("taylor_test: direction has the wrong size");
    return options.direction;
  }
  std::mt19937 rng(options.seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vector dz(z.size());
  for (Eigen::Index i = 0; i < z.size(); ++i)
    dz[i] = u(rng) * std::max(std::abs(z[i]), options.direction_floor);
  return dz;
}

// One evaluation at step h: (J(z + h dz), r0(h), r1(h)).
// The fourth entry is the magnitude of what was evaluated (|J(z + h dz)| or ||g(z + h dz)||):
// the noise floor grows with it (round-off of large values far from z).
using Remainders = std::function<std::array<double, 4>(double)>;

double rate_between(const TaylorRow& a, const TaylorRow& b, double TaylorRow::*remainder) {
  return std::log(a.*remainder / b.*remainder) / std::log(a.step / b.step);
}

// The search and the verdict described in taylor_test.hpp. `slope` is |first-order term| per
// unit step (|dJ.dz| or ||H dz||), `noise` the evaluation noise floor of the remainders at z
// (fixed when options.noise_floor is set, else grown with the evaluated magnitude).
void judge(TaylorTestResult& result, const TaylorTestOptions& options, double slope, double noise,
           const Remainders& remainders) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const int halvings = std::max(options.halvings, 4);
  const double fraction = options.asymptotic_fraction;
  // r1 falls 4x per halving: to stay 10x above the noise for three halvings it starts >= 640x.
  constexpr double kResolvable = 10.0 * 64.0;
  // Steps are relative to dz, which is scaled like z: beyond h = 1 the test would leave z's scale.
  const double max_step = std::max(1.0, options.initial_step);
  auto evaluate = [&](double h, bool judged) {
    const auto [value, r0, r1, magnitude] = remainders(h);
    const double row_noise = options.noise_floor > 0.0
                                 ? noise
                                 : std::max(noise, 1e3 * std::numeric_limits<double>::epsilon() * magnitude);
    result.rows.push_back(TaylorRow{h, value, r0, r1, nan, nan, r1 <= 10.0 * row_noise, row_noise, judged});
    return result.rows.back();  // a copy: later pushes may move the rows
  };
  std::ostringstream msg;
  if (slope * max_step <= 10.0 * noise) {
    result.status = TaylorStatus::vanishing;
    msg << "the directional derivative vanishes (first-order term " << slope * max_step
        << " at h = " << max_step << " is at the noise floor " << noise
        << "): nothing was tested; choose another point or direction";
    result.message = msg.str();
    return;
  }

  // 1. The search for a step in the asymptotic regime with a resolvable remainder.
  double h = options.initial_step;
  double smallest_too_large = std::numeric_limits<double>::infinity();  // r1 > fraction * t
  double largest_too_small = 0.0;                                       // r1 below `resolvable`
  bool found = false;
  for (int s = 0; s < std::max(options.max_search_steps, 1); ++s) {
    const TaylorRow row = evaluate(h, false);
    const double t = slope * h;
    const bool asymptotic = row.remainder1 <= fraction * t;
    if (asymptotic && row.remainder1 >= kResolvable * row.noise) {
      found = true;
      result.rows.back().judged = true;  // the first of the judged rows
      break;
    }
    if (asymptotic)
      largest_too_small = std::max(largest_too_small, h);
    else
      smallest_too_large = std::min(smallest_too_large, h);
    if (largest_too_small > 0.0 && std::isfinite(smallest_too_large)) {
      if (smallest_too_large < 1.2 * largest_too_small) break;  // no window between the two
      h = std::sqrt(smallest_too_large * largest_too_small);
    } else if (!asymptotic) {
      // For a right gradient r1 / t ~ h: jump to a quarter of the allowed fraction.
      h *= std::clamp(0.25 * fraction * t / row.remainder1, 1e-3, 0.5);
    } else {
      // r1 ~ h^2: grow to four times the resolvable level, but not beyond z's scale.
      if (h >= max_step) break;
      const double needed = 4.0 * kResolvable * row.noise;
      h = std::min(
          max_step,
          h * (row.remainder1 > 0.0 ? std::clamp(std::sqrt(needed / row.remainder1), 2.0, 1e3) : 1e3));
    }
  }
  if (!found) {
    // Did the remainder stay a fixed fraction of the first-order term as h shrank (a wrong
    // derivative: r1 ~ h), or did it fall faster but meet the noise first?
    std::vector<double> rates;
    std::vector<TaylorRow> informative;
    for (const TaylorRow& r : result.rows)
      if (!r.round_off && r.remainder1 > fraction * slope * r.step) informative.push_back(r);
    std::sort(informative.begin(), informative.end(),
              [](const auto& a, const auto& b) { return a.step > b.step; });
    for (std::size_t k = 1; k < informative.size(); ++k)
      if (informative[k - 1].step > 1.5 * informative[k].step)
        rates.push_back(rate_between(informative[k - 1], informative[k], &TaylorRow::remainder1));
    result.rate1 = median(rates);
    if (!rates.empty() && result.rate1 < 1.5) {
      result.status = TaylorStatus::failed;
      msg << "the remainder stays a fixed fraction (about " << std::setprecision(2)
          << informative.back().remainder1 / (slope * informative.back().step)
          << ") of the first-order term as h shrinks (rate " << std::fixed << std::setprecision(2)
          << result.rate1 << "): the derivative is wrong";
    } else if (largest_too_small == 0.0 && !std::isfinite(smallest_too_large)) {
      result.status = TaylorStatus::round_off;
      msg << "no step gave a remainder above the noise floor " << noise << " (up to h = " << max_step << ")";
    } else if (!std::isfinite(smallest_too_large)) {
      result.status = TaylorStatus::round_off;
      msg << "the second-order remainder stayed within 640x of the noise floor " << noise
          << " up to h = " << largest_too_small << ": the functional is (nearly) linear along dz, or its "
          << "evaluations are too noisy; tighten the forward solve";
    } else {
      result.status = TaylorStatus::not_asymptotic;
      msg << "no step is both asymptotic (remainder <= " << fraction << " x first-order term, needs h < "
          << smallest_too_large << ") and above the noise floor " << noise << " (needs h > "
          << largest_too_small << "): tighten the forward solve or scale the design";
    }
    result.message = msg.str();
    return;
  }

  // 2. The verdict over `halvings` halvings from the step found.
  result.step = h;
  std::vector<double> rates0, rates1;
  for (int k = 1; k <= halvings; ++k) {
    h *= 0.5;
    const TaylorRow prev = result.rows.back();
    TaylorRow& row = (evaluate(h, true), result.rows.back());
    if (row.remainder0 > 10.0 * row.noise && prev.remainder0 > 10.0 * prev.noise) {
      row.rate0 = std::log2(prev.remainder0 / row.remainder0);
      rates0.push_back(row.rate0);
    }
    if (!row.round_off && !prev.round_off) {
      row.rate1 = std::log2(prev.remainder1 / row.remainder1);
      rates1.push_back(row.rate1);
    }
  }
  result.rate0 = median(rates0);
  result.rate1 = median(rates1);
  msg << std::fixed << std::setprecision(2);
  if (rates1.size() < 3) {
    result.status = TaylorStatus::not_asymptotic;
    msg << "only " << rates1.size() << " rates above the noise floor from h = " << std::scientific
        << result.step << ": tighten the forward solve";
  } else if (!(std::abs(result.rate0 - 1.0) <= options.first_rate_tolerance)) {
    result.status = TaylorStatus::not_asymptotic;
    msg << "the first-order difference falls at rate " << result.rate0
        << ", not 1: not in the asymptotic regime";
  } else if (result.rate1 >= options.min_rate) {
    result.status = TaylorStatus::passed;
    msg << "first-order difference at rate " << result.rate0 << ", second-order remainder at rate "
        << result.rate1 << " from h = " << std::scientific << std::setprecision(2) << result.step;
  } else {
    result.status = TaylorStatus::failed;
    msg << "second-order remainder converges at rate " << result.rate1 << " < " << options.min_rate
        << " (first-order rate " << result.rate0
        << "): the derivative is wrong (or the functional is not smooth here)";
  }
  result.message = msg.str();
}

}  // namespace

TaylorTestResult taylor_test(ReducedFunctional& functional, const Vector& z,
                             const TaylorTestOptions& options) {
  TaylorTestResult result;
  try {
    result.direction = random_direction(z, options);
    const Vector& dz = result.direction;
    Vector gradient;
    result.value = functional.value_and_gradient(z, gradient);
    result.directional_derivative = gradient.dot(dz);
    const double noise = options.noise_floor > 0.0 ? options.noise_floor
                                                   : 1e3 * std::numeric_limits<double>::epsilon() *
                                                         std::max(std::abs(result.value), 1e-300);
    judge(result, options, std::abs(result.directional_derivative), noise, [&](double h) {
      const double value = functional.value(z + h * dz);
      return std::array<double, 4>{value, std::abs(value - result.value),
                                   std::abs(value - result.value - h * result.directional_derivative),
                                   std::abs(value)};
    });
  } catch (const std::exception& e) {
    result.status = TaylorStatus::evaluation_failed;
    result.message = std::string("evaluation failed: ") + e.what();
  }
  return result;
}

TaylorTestResult taylor_test_hessian(ReducedFunctional& functional, const Vector& z,
                                     const TaylorTestOptions& options) {
  TaylorTestResult result;
  try {
    if (!functional.has_hessian_vector())
      throw std::logic_error("the functional offers no Hessian-vector products");
    result.direction = random_direction(z, options);
    const Vector& dz = result.direction;
    Vector gradient;
    result.value = functional.value_and_gradient(z, gradient);
    const Vector hv = functional.hessian_vector(z, dz);
    result.directional_derivative = hv.norm();
    const double noise = options.noise_floor > 0.0 ? options.noise_floor
                                                   : 1e3 * std::numeric_limits<double>::epsilon() *
                                                         std::max(gradient.norm(), 1e-300);
    judge(result, options, hv.norm(), noise, [&](double h) {
      Vector g;
      const double value = functional.value_and_gradient(z + h * dz, g);
      return std::array<double, 4>{value, (g - gradient).norm(), (g - gradient - h * hv).norm(), g.norm()};
    });
  } catch (const std::exception& e) {
    result.status = TaylorStatus::evaluation_failed;
    result.message = std::string("evaluation failed: ") + e.what();
  }
  return result;
}

std::string TaylorTestResult::table() const {
  std::ostringstream s;
  s << "Taylor test: J = " << std::setprecision(10) << value << ", dJ.dz = " << directional_derivative
    << "\n";
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
      << r.remainder0 << "   " << rate(r.rate0) << "   " << std::setw(20) << r.remainder1 << "   "
      << rate(r.rate1) << (r.round_off ? "  (round-off)" : "") << (r.judged ? "" : "  (search)") << "\n";
  }
  s << to_string(status) << ": " << message << "\n";
  return s.str();
}

}  // namespace tailor
