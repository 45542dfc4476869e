// Box constraints by reparameterization: p_i = lower_i + (upper_i - lower_i) (1 + tanh z_i) / 2.
#include <cmath>

#include "adjoint/parameterizations/checked_map.hpp"

namespace tailor {
namespace {

using detail::concat;

// (1 + tanh z) / 2 is the logistic function s = 1 / (1 + exp(-2z)). Evaluating it as
// 1 + tanh(z) cancels catastrophically for z << 0 (and 1 - s likewise for z >> 0), which would
// make the derivatives, 2 s (1 - s), lose all relative accuracy in the tails. So both s and
// 1 - s are formed from exp(-2|z|) <= 1, each without cancellation.
struct Logistic {
  double s;   // (1 + tanh z) / 2
  double sc;  // 1 - s = (1 - tanh z) / 2
};

Logistic logistic(double z) {
  const double e = std::exp(-2.0 * std::abs(z));
  const double big = 1.0 / (1.0 + e), small = e / (1.0 + e);
  return z >= 0 ? Logistic{big, small} : Logistic{small, big};
}

class BoundsMap final : public detail::CheckedMap {
 public:
  BoundsMap(Vector lower, Vector upper) : lower_(std::move(lower)), width_(std::move(upper) - lower_) {}
  std::string name() const override { return concat("bounds(", lower_.size(), ")"); }
  int num_design() const override { return static_cast<int>(lower_.size()); }
  int num_params() const override { return static_cast<int>(lower_.size()); }

 protected:
  Vector do_apply(const Vector& z) const override {
    Vector p(z.size());
    for (Eigen::Index i = 0; i < z.size(); ++i) p[i] = lower_[i] + width_[i] * logistic(z[i]).s;
    return p;
  }
  Vector do_jacobian_times(const Vector& z, const Vector& dz) const override {
    return (slope(z).array() * dz.array()).matrix();
  }
  Vector do_jacobian_transpose_times(const Vector& z, const Vector& w) const override {
    return (slope(z).array() * w.array()).matrix();
  }
  // d2p_i/dz_i^2 = width_i * 4 s (1 - s) (1 - 2 s), i.e. -width_i tanh(z_i) sech^2(z_i).
  Vector do_second_derivative_times(const Vector& z, const Vector& w, const Vector& dz) const override {
    Vector out(z.size());
    for (Eigen::Index i = 0; i < z.size(); ++i) {
      const Logistic l = logistic(z[i]);
      out[i] = w[i] * width_[i] * 4.0 * l.s * l.sc * (l.sc - l.s) * dz[i];
    }
    return out;
  }

 private:
  // dp_i/dz_i = width_i * 2 s (1 - s) = width_i sech^2(z_i) / 2.
  Vector slope(const Vector& z) const {
    Vector d(z.size());
    for (Eigen::Index i = 0; i < z.size(); ++i) {
      const Logistic l = logistic(z[i]);
      d[i] = width_[i] * 2.0 * l.s * l.sc;
    }
    return d;
  }

  Vector lower_;
  Vector width_;  // upper - lower > 0
};

}  // namespace

ParameterizationPtr bounds_map(Vector lower, Vector upper) {
  if (lower.size() != upper.size())
    detail::invalid_parameterization(
        "bounds_map", concat("lower has size ", lower.size(), " but upper has size ", upper.size()));
  for (Eigen::Index i = 0; i < lower.size(); ++i) {
    if (!std::isfinite(lower[i]) || !std::isfinite(upper[i]) || !std::isfinite(upper[i] - lower[i]))
      detail::invalid_parameterization(
          "bounds_map",
          concat("bounds must be finite, got lower[", i, "] = ", lower[i], ", upper[", i, "] = ", upper[i]));
    if (!(lower[i] < upper[i]))
      detail::invalid_parameterization(
          "bounds_map", concat("lower must be below upper, but lower[", i, "] = ", lower[i], " >= upper[", i,
                               "] = ", upper[i]));
  }
  return std::make_shared<BoundsMap>(std::move(lower), std::move(upper));
}

}  // namespace tailor
