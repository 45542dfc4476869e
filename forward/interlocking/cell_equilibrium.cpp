// Newton on the periodic cell's contact barrier (see cell_equilibrium.hpp).
#include "forward/interlocking/cell_equilibrium.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace tailor::interlocking {

ReducedContact reduced_contact(const PeriodicRigidCell& cell, const Vector& x, bool hessian, HessianMode mode) {
  ReducedContact out;
  const Vector p = cell.radii_parameters();
  out.full_gradient = Vector::Zero(x.size());
  EnergyRequest request;
  request.value = &out.energy;
  request.gradient = &out.full_gradient;
  cell.contact().evaluate(x, p, request);
  out.gradient = cell.basis().transpose() * out.full_gradient;
  if (hessian && std::isfinite(out.energy)) {
    out.full_hessian = cell.contact().hessian(x, p, mode);
    const SparseMatrix SH = cell.basis().transpose() * out.full_hessian;
    out.hessian = Matrix(SH * cell.basis());
  }
  return out;
}

double smallest_distance(const PeriodicRigidCell& cell, const Vector& x, double range) {
  return cell.contact().min_distance(x, cell.radii_parameters(), range);
}

namespace {

CellSolveResult newton(const PeriodicRigidCell& cell, const Eigen::Matrix2d& F, const Vector& y_start,
                       const CellSolveOptions& options) {
  CellSolveResult result;
  result.y = y_start;
  const Vector x0 = cell.offset(F);
  const SparseMatrix& S = cell.basis();
  for (int it = 0;; ++it) {
    const Vector x = x0 + S * result.y;
    const ReducedContact c = reduced_contact(cell, x, true, HessianMode::projected);
    result.energy = c.energy;
    result.iterations = it;
    if (!std::isfinite(c.energy)) {
      result.message = "the state intersects (infinite barrier)";
      return result;
    }
    result.residual = c.gradient.size() ? c.gradient.lpNorm<Eigen::Infinity>() : 0.0;
    if (result.residual <= options.force_tolerance) {
      result.converged = true;
      return result;
    }
    if (it >= options.max_iterations) {
      result.message = "Newton reached " + std::to_string(it) + " iterations, residual " + std::to_string(result.residual);
      return result;
    }
    Matrix H = c.hessian;
    const double mu = options.regularization * (1.0 + H.diagonal().cwiseAbs().maxCoeff());
    H.diagonal().array() += mu;
    const Vector dy = H.ldlt().solve(-c.gradient);
    const Vector dx = S * dy;
    double alpha = std::min(1.0, cell.contact().max_step(x, dx));
    const double slope = c.gradient.dot(dy);
    bool accepted = false;
    for (int ls = 0; ls < options.max_line_search_steps && alpha > 0.0; ++ls, alpha *= 0.5) {
      double e = 0.0;
      EnergyRequest request;
      request.value = &e;
      cell.contact().evaluate(x + alpha * dx, cell.radii_parameters(), request);
      if (std::isfinite(e) && e <= c.energy + 1e-4 * alpha * slope) {
        accepted = true;
        break;
      }
    }
    if (!accepted) {
      // The energy cannot resolve the decrease any more: accept the residual if it is small
      // relative to the force scale, else report the stall.
      result.message = "line search failed at residual " + std::to_string(result.residual);
      result.converged = result.residual <= std::sqrt(options.force_tolerance);
      return result;
    }
    result.y += alpha * dy;
  }
}

}  // namespace

CellSolveResult solve_cell_equilibrium(const PeriodicRigidCell& cell, const Eigen::Matrix2d& F,
                                       const Vector& y_start, const CellSolveOptions& options) {
  try {
    return newton(cell, F, y_start, options);
  } catch (const std::runtime_error& e) {  // a degenerate (coaxial) pair in contact
    CellSolveResult result;
    result.y = y_start;
    result.message = e.what();
    return result;
  }
}

}  // namespace tailor::interlocking
