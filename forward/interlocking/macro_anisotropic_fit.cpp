// The spherical-harmonic fit of an anisotropic strain-space boundary (see macro_anisotropic_fit.hpp).
#include "forward/interlocking/macro_anisotropic_fit.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace tailor::interlocking {
namespace {

// (rho, u, v, w) of a strain (e_xx, e_yy, e_xy): the header's size and direction.
double direction_of(const Eigen::Vector3d& e, double& u, double& v, double& w) {
  const double rho = std::sqrt(e.x() * e.x() + e.y() * e.y() + 2.0 * e.z() * e.z());
  if (!(rho > 0.0)) {
    u = 1.0;
    v = w = 0.0;
    return rho;
  }
  u = (e.x() + e.y()) / (std::sqrt(2.0) * rho);
  v = (e.x() - e.y()) / (std::sqrt(2.0) * rho);
  w = std::sqrt(2.0) * e.z() / rho;
  return rho;
}

int basis_size(int degree, int max_order) {
  int n = 0;
  for (int m = 0; m <= max_order; ++m) n += (m == 0 ? 1 : 2) * (degree - m + 1);
  return n;
}

// Row of the design matrix at a unit direction: the basis functions themselves (the radius with
// one coefficient set to 1).
void basis_row(AnisotropicBoundaryFit& fit, double u, double v, double w, double* row) {
  const int n = static_cast<int>(fit.coefficients.size());
  for (int k = 0; k < n; ++k) {
    fit.coefficients.assign(static_cast<std::size_t>(n), 0.0);
    fit.coefficients[static_cast<std::size_t>(k)] = 1.0;
    row[k] = fit.radius(u, v, w);
  }
}

}  // namespace

double AnisotropicBoundaryFit::radius_along(const Eigen::Vector3d& strain) const {
  double u = 0.0, v = 0.0, w = 0.0;
  direction_of(strain, u, v, w);
  return radius(u, v, w);
}

double MacroStrainSet::radius_along(const Eigen::Vector3d& strain) const {
  double u = 0.0, v = 0.0, w = 0.0;
  direction_of(strain, u, v, w);
  return radius(u, v, w);
}

double MacroStrainSet::margin(const Eigen::Vector3d& strain) const {
  double u = 0.0, v = 0.0, w = 0.0;
  const double rho = direction_of(strain, u, v, w);
  return 1.0 - rho / radius(u, v, w);
}

AnisotropicBoundaryFit fit_anisotropic_boundary(const std::vector<Eigen::Vector3d>& limit_strains, int degree,
                                                int max_order, const StrainSetSymmetry& symmetry) {
  if (degree < 0 || max_order < 0 || max_order > degree)
    throw std::invalid_argument("fit_anisotropic_boundary: needs 0 <= max_order <= degree");
  std::vector<Eigen::Vector3d> points;  // the samples and their mirror images
  for (std::size_t i = 0; i < limit_strains.size(); ++i) {
    const Eigen::Vector3d& e = limit_strains[i];
    if (!e.allFinite() || !(e.norm() > 0.0))
      throw std::invalid_argument("fit_anisotropic_boundary: sample " + std::to_string(i) +
                                  " is at the origin or not finite");
    points.push_back(e);
    if (symmetry.reflect) points.emplace_back(e.x(), e.y(), -e.z());
    if (symmetry.swap) points.emplace_back(e.y(), e.x(), e.z());
    if (symmetry.reflect && symmetry.swap) points.emplace_back(e.y(), e.x(), -e.z());
  }
  AnisotropicBoundaryFit fit;
  fit.degree = degree;
  fit.max_order = max_order;
  const int n = basis_size(degree, max_order);
  const int m = static_cast<int>(points.size());
  fit.coefficients.assign(static_cast<std::size_t>(n), 0.0);
  std::vector<Eigen::Vector3d> distinct;
  Eigen::MatrixXd design(m, n);
  Eigen::VectorXd rho(m);
  std::vector<double> row(static_cast<std::size_t>(n));
  for (int i = 0; i < m; ++i) {
    double u = 0.0, v = 0.0, w = 0.0;
    rho[i] = direction_of(points[static_cast<std::size_t>(i)], u, v, w);
    basis_row(fit, u, v, w, row.data());
    for (int k = 0; k < n; ++k) design(i, k) = row[static_cast<std::size_t>(k)];
    const Eigen::Vector3d d(u, v, w);
    if (std::none_of(distinct.begin(), distinct.end(), [&](const Eigen::Vector3d& o) { return (o - d).norm() < 1e-9; }))
      distinct.push_back(d);
  }
  if (static_cast<int>(distinct.size()) < n)
    throw std::invalid_argument("fit_anisotropic_boundary: " + std::to_string(distinct.size()) +
                                " distinct directions (mirror images included) cannot fix the " +
                                std::to_string(n) + " coefficients of degree " + std::to_string(degree) +
                                ", order " + std::to_string(max_order));
  fit.coefficients = least_squares(design, rho);
  fit.samples = static_cast<int>(limit_strains.size());
  double squares = 0.0;
  for (std::size_t i = 0; i < limit_strains.size(); ++i) {
    double u = 0.0, v = 0.0, w = 0.0;
    const double size = direction_of(limit_strains[i], u, v, w);
    const double residual = std::abs(fit.radius(u, v, w) - size);
    squares += residual * residual;
    fit.max_residual = std::max(fit.max_residual, residual);
  }
  fit.rms_residual = std::sqrt(squares / static_cast<double>(limit_strains.size()));
  fit.min_radius = fit.radius(1.0, 0.0, 0.0);
  for (int i = 0; i <= 90; ++i)
    for (int j = 0; j < 180; ++j) {
      const double phi = M_PI * i / 90, beta = 2.0 * M_PI * j / 180;
      fit.min_radius = std::min(
          fit.min_radius, fit.radius(std::cos(phi), std::sin(phi) * std::cos(beta), std::sin(phi) * std::sin(beta)));
    }
  if (!(fit.min_radius > 0.0))
    throw std::invalid_argument(
        "fit_anisotropic_boundary: the fitted radius is not positive on the whole sphere (lower the degree "
        "or add directions)");
  return fit;
}

}  // namespace tailor::interlocking
