#include "forward/dynamics/monotone_spline.hpp"

#include <cmath>
#include <stdexcept>

namespace tailor {

MonotoneCubic::MonotoneCubic(Vector knots) : knots_(std::move(knots)) {
  if (knots_.size() < 1) throw std::invalid_argument("MonotoneCubic: at least one knot is needed");
  for (Eigen::Index k = 0; k < knots_.size(); ++k) {
    if (!std::isfinite(knots_[k])) throw std::invalid_argument("MonotoneCubic: knots must be finite");
    if (k > 0 && !(knots_[k] > knots_[k - 1]))
      throw std::invalid_argument("MonotoneCubic: knots must be strictly increasing (knot " +
                                  std::to_string(k) + ")");
  }
}

namespace {

// Slope at knot k and its derivatives in y_{k-1}, y_k, y_{k+1} (dm[0..2]).
double knot_slope(const Vector& t, const Vector& y, Eigen::Index k, double dm[3]) {
  const Eigen::Index n = t.size();
  dm[0] = dm[1] = dm[2] = 0.0;
  if (k == 0) {  // end secant
    const double h = t[1] - t[0];
    dm[1] = -1.0 / h, dm[2] = 1.0 / h;
    return (y[1] - y[0]) / h;
  }
  if (k == n - 1) {
    const double h = t[k] - t[k - 1];
    dm[0] = -1.0 / h, dm[1] = 1.0 / h;
    return (y[k] - y[k - 1]) / h;
  }
  const double h0 = t[k] - t[k - 1], h1 = t[k + 1] - t[k];
  const double d0 = (y[k] - y[k - 1]) / h0, d1 = (y[k + 1] - y[k]) / h1;
  if (!(d0 * d1 > 0.0)) return 0.0;
  const double w1 = 2.0 * h1 + h0, w2 = h1 + 2.0 * h0;
  const double den = w1 / d0 + w2 / d1;
  const double m = (w1 + w2) / den;
  // dm/dd0 = (w1 + w2) w1 / (d0^2 den^2), likewise for d1.
  const double dm_dd0 = (w1 + w2) * w1 / (d0 * d0 * den * den);
  const double dm_dd1 = (w1 + w2) * w2 / (d1 * d1 * den * den);
  dm[0] = -dm_dd0 / h0;
  dm[1] = dm_dd0 / h0 - dm_dd1 / h1;
  dm[2] = dm_dd1 / h1;
  return m;
}

}  // namespace

double MonotoneCubic::evaluate(const Vector& y, double t, double* slope, Vector* control_gradient) const {
  const Eigen::Index n = knots_.size();
  if (y.size() != n)
    throw std::invalid_argument("MonotoneCubic: " + std::to_string(y.size()) + " control values for " +
                                std::to_string(n) + " knots");
  if (control_gradient) control_gradient->setZero(n);
  if (slope) *slope = 0.0;
  if (n == 1 || t <= knots_[0]) {
    if (control_gradient) (*control_gradient)[0] = 1.0;
    return y[0];
  }
  if (t >= knots_[n - 1]) {
    if (control_gradient) (*control_gradient)[n - 1] = 1.0;
    return y[n - 1];
  }
  Eigen::Index k = 0;
  while (t > knots_[k + 1]) ++k;
  const double h = knots_[k + 1] - knots_[k];
  const double s = (t - knots_[k]) / h;
  double dm0[3], dm1[3];
  const double m0 = knot_slope(knots_, y, k, dm0);
  const double m1 = knot_slope(knots_, y, k + 1, dm1);
  // Cubic Hermite basis on [0, 1] and its derivatives.
  const double s2 = s * s, s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  if (slope) {
    const double d00 = 6 * s2 - 6 * s, d10 = 3 * s2 - 4 * s + 1, d01 = -6 * s2 + 6 * s, d11 = 3 * s2 - 2 * s;
    *slope = (d00 * y[k] + d10 * h * m0 + d01 * y[k + 1] + d11 * h * m1) / h;
  }
  if (control_gradient) {
    Vector& g = *control_gradient;
    g[k] += h00;
    g[k + 1] += h01;
    for (int j = 0; j < 3; ++j) {
      const Eigen::Index i0 = k - 1 + j, i1 = k + j;  // the y entries m0 and m1 depend on
      if (i0 >= 0 && i0 < n) g[i0] += h10 * h * dm0[j];
      if (i1 >= 0 && i1 < n) g[i1] += h11 * h * dm1[j];
    }
  }
  return h00 * y[k] + h10 * h * m0 + h01 * y[k + 1] + h11 * h * m1;
}

}  // namespace tailor
