// Polar Chebyshev fit of a measured strain-space boundary (see macro_boundary_fit.hpp).
#include "forward/interlocking/macro_boundary_fit.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "forward/core/symmetric_eigen.hpp"

namespace tailor::interlocking {
namespace {

// (rho, c) of principal strains e: the polar form of the header.
void polar(const Eigen::Vector2d& e, double& rho, double& c) {
  rho = e.norm();
  c = rho > 0.0 ? std::clamp((e.x() + e.y()) / (std::sqrt(2.0) * rho), -1.0, 1.0) : 1.0;
}

}  // namespace

double BoundaryFit::radius_at_angle(double angle) const {
  double rho = 0.0, c = 0.0;
  polar(Eigen::Vector2d(std::cos(angle), std::sin(angle)), rho, c);
  return radius(c);
}

BoundaryFit fit_boundary(const std::vector<Eigen::Vector2d>& limit_strains, int order) {
  if (order < 0) throw std::invalid_argument("fit_boundary: the order must be >= 0");
  const int m = static_cast<int>(limit_strains.size());
  const int n = order + 1;
  Eigen::MatrixXd A(m, n);
  Eigen::VectorXd rho(m);
  std::vector<double> distinct;
  for (int i = 0; i < m; ++i) {
    double c = 0.0;
    polar(limit_strains[static_cast<std::size_t>(i)], rho[i], c);
    if (!(rho[i] > 0.0) || !std::isfinite(rho[i]))
      throw std::invalid_argument("fit_boundary: sample " + std::to_string(i) + " is at the origin or not finite");
    double t_prev = 1.0, t = c;
    for (int k = 0; k < n; ++k) {
      A(i, k) = k == 0 ? 1.0 : t;
      if (k >= 1) {
        const double t_next = 2.0 * c * t - t_prev;
        t_prev = t;
        t = t_next;
      }
    }
    if (std::none_of(distinct.begin(), distinct.end(), [&](double d) { return std::abs(d - c) < 1e-9; }))
      distinct.push_back(c);
  }
  if (static_cast<int>(distinct.size()) < n)
    throw std::invalid_argument("fit_boundary: " + std::to_string(distinct.size()) +
                                " distinct directions (mirror images count once) cannot fix order " +
                                std::to_string(order));
  // Normal equations, solved through the compiled-once symmetric eigen-decomposition (n <= ~10;
  // the Chebyshev basis keeps A^T A well conditioned on [-1, 1]).
  const Eigen::MatrixXd N = A.transpose() * A;
  const Eigen::VectorXd b = A.transpose() * rho;
  Eigen::VectorXd values(n);
  Eigen::MatrixXd vectors(n, n);
  symmetric_eigen<Eigen::Dynamic>(N, values, vectors);
  Eigen::VectorXd coefficients = Eigen::VectorXd::Zero(n);
  for (int k = 0; k < n; ++k)
    if (values[k] > 1e-12 * values[n - 1]) coefficients += vectors.col(k) * (vectors.col(k).dot(b) / values[k]);
  BoundaryFit fit;
  fit.coefficients.assign(coefficients.data(), coefficients.data() + n);
  fit.samples = m;
  const Eigen::VectorXd residual = A * coefficients - rho;
  fit.rms_residual = std::sqrt(residual.squaredNorm() / m);
  fit.max_residual = residual.cwiseAbs().maxCoeff();
  fit.min_radius = fit.radius(1.0);
  for (int k = 0; k <= 2000; ++k) fit.min_radius = std::min(fit.min_radius, fit.radius(-1.0 + k / 1000.0));
  if (!(fit.min_radius > 0.0))
    throw std::invalid_argument("fit_boundary: the fitted radius is not positive everywhere (lower the order)");
  return fit;
}

double boundary_margin(const BoundaryFit& fit, const Eigen::Vector2d& principal_strains) {
  double rho = 0.0, c = 0.0;
  polar(principal_strains, rho, c);
  return 1.0 - rho / fit.radius(c);
}

}  // namespace tailor::interlocking
