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

std::vector<double> least_squares(const Eigen::MatrixXd& design, const Eigen::VectorXd& values) {
  // Normal equations, solved through the compiled-once symmetric eigen-decomposition (n up to a
  // few dozen; the orthogonal bases of the fits keep A^T A well conditioned); directions the
  // samples do not fix (eigenvalues below 1e-12 of the largest) get no coefficient.
  // Plain loops rather than dynamic Eigen products: this file stays cheap to compile.
  const int m = static_cast<int>(design.rows()), n = static_cast<int>(design.cols());
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(n, n);
  std::vector<double> b(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < m; ++i)
    for (int k = 0; k < n; ++k) {
      b[static_cast<std::size_t>(k)] += design(i, k) * values[i];
      for (int l = 0; l < n; ++l) N(k, l) += design(i, k) * design(i, l);
    }
  Eigen::VectorXd eigenvalues(n);
  Eigen::MatrixXd vectors(n, n);
  symmetric_eigen<Eigen::Dynamic>(N, eigenvalues, vectors);
  std::vector<double> coefficients(static_cast<std::size_t>(n), 0.0);
  for (int k = 0; k < n; ++k) {
    if (!(eigenvalues[k] > 1e-12 * eigenvalues[n - 1])) continue;
    double vb = 0.0;
    for (int l = 0; l < n; ++l) vb += vectors(l, k) * b[static_cast<std::size_t>(l)];
    for (int l = 0; l < n; ++l) coefficients[static_cast<std::size_t>(l)] += vectors(l, k) * vb / eigenvalues[k];
  }
  return coefficients;
}

BoundaryFit fit_boundary(const std::vector<Eigen::Vector2d>& limit_strains, int order) {
  if (order < 0) throw std::invalid_argument("fit_boundary: the order must be >= 0");
  const int m = static_cast<int>(limit_strains.size());
  const int n = order + 1;
  std::vector<double> A(static_cast<std::size_t>(m) * n), rho(static_cast<std::size_t>(m));
  std::vector<double> distinct;
  for (int i = 0; i < m; ++i) {
    double c = 0.0;
    polar(limit_strains[static_cast<std::size_t>(i)], rho[static_cast<std::size_t>(i)], c);
    if (!(rho[static_cast<std::size_t>(i)] > 0.0) || !std::isfinite(rho[static_cast<std::size_t>(i)]))
      throw std::invalid_argument("fit_boundary: sample " + std::to_string(i) +
                                  " is at the origin or not finite");
    double t_prev = 1.0, t = c;  // T_0, T_1
    for (int k = 0; k < n; ++k) {
      A[static_cast<std::size_t>(i * n + k)] = k == 0 ? 1.0 : t;
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
  Eigen::MatrixXd design(m, n);
  for (int i = 0; i < m; ++i)
    for (int k = 0; k < n; ++k) design(i, k) = A[static_cast<std::size_t>(i * n + k)];
  const std::vector<double> coefficients =
      least_squares(design, Eigen::Map<const Eigen::VectorXd>(rho.data(), m));
  BoundaryFit fit;
  fit.coefficients = coefficients;
  fit.samples = m;
  double squares = 0.0;
  for (int i = 0; i < m; ++i) {
    double r = 0.0;
    for (int k = 0; k < n; ++k)
      r += A[static_cast<std::size_t>(i * n + k)] * coefficients[static_cast<std::size_t>(k)];
    const double residual = std::abs(r - rho[static_cast<std::size_t>(i)]);
    squares += residual * residual;
    fit.max_residual = std::max(fit.max_residual, residual);
  }
  fit.rms_residual = std::sqrt(squares / m);
  fit.min_radius = fit.radius(1.0);
  for (int k = 0; k <= 2000; ++k) fit.min_radius = std::min(fit.min_radius, fit.radius(-1.0 + k / 1000.0));
  if (!(fit.min_radius > 0.0))
    throw std::invalid_argument(
        "fit_boundary: the fitted radius is not positive everywhere (lower the order)");
  return fit;
}

double boundary_margin(const BoundaryFit& fit, const Eigen::Vector2d& principal_strains) {
  double rho = 0.0, c = 0.0;
  polar(principal_strains, rho, c);
  return 1.0 - rho / fit.radius(c);
}

}  // namespace tailor::interlocking
