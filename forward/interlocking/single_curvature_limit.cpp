// Ramping a single curvature on a periodic cell until it locks (see single_curvature_limit.hpp).
#include "forward/interlocking/single_curvature_limit.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "forward/core/psd_projection.hpp"
#include "forward/core/symmetric_eigen.hpp"
#include "forward/tori/torus_distance.hpp"

namespace tailor::interlocking {
namespace {

// H^+ b for a symmetric H (eigenvalues below 1e-10 of the largest dropped; see
// limit_sensitivity.hpp for why the null modes are consistent).
Vector curved_pseudo_solve(const Matrix& H, const Vector& b) {
  Vector values;
  Matrix vectors;
  symmetric_eigen<Eigen::Dynamic>(H, values, vectors);
  const double cut = 1e-10 * values.cwiseAbs().maxCoeff();
  Vector c = vectors.transpose() * b;
  for (int i = 0; i < values.size(); ++i) c[i] = std::abs(values[i]) > cut ? c[i] / values[i] : 0.0;
  return vectors * c;
}

CellSolveResult curved_newton(const SingleCurvatureCell& curved, double kappa, const Vector& y_start,
                              const CellSolveOptions& options) {
  const PeriodicRigidCell& cell = curved.cell();
  return levenberg_newton(y_start, options, 1e-10, [&](const Vector& y) {
    // The exact reduced Hessian where it is positive definite (quadratic convergence near the
    // equilibrium), else the Gauss-Newton matrix J^T H+ J (curved_periodicity.hpp).
    SingleCurvatureCell::Reduced c = curved.reduce(y, kappa, true, HessianMode::exact);
    if (std::isfinite(c.energy) && !cholesky_accepts<Eigen::Dynamic>(c.hessian))
      c.hessian = curved.reduce(y, kappa, true, HessianMode::projected).hessian;
    CellNewtonPoint point{c.energy, std::move(c.gradient), std::move(c.hessian), {}, {}};
    point.max_step = [&, y, x = c.x](const Vector& dy) {
      return contact_max_step(cell, x, curved.full_state(y + dy, kappa) - x);
    };
    point.energy_along = [&, y](double alpha, const Vector& dy) {
      return contact_energy(cell, curved.full_state(y + alpha * dy, kappa));
    };
    return point;
  });
}

// The equilibrium path's tangent dy/ds (zero where no pair is within d_hat).
Vector curved_tangent(const SingleCurvatureCell& curved, const Vector& y, double kappa, double sign) {
  const SingleCurvatureCell::Reduced c = curved.reduce(y, kappa, true, HessianMode::exact);
  if (!(c.energy > 0.0) || !std::isfinite(c.energy)) return Vector::Zero(y.size());
  return -sign * curved_pseudo_solve(c.hessian, c.mixed);
}

RampResult curved_ramp(const SingleCurvatureCell& curved, double sign, const Vector& y_from, double s_from,
                       double s_to, const LimitOptions& options, int& solves) {
  const PeriodicRigidCell& cell = curved.cell();
  RampResult r;
  r.s = r.s_unlocked = s_from;
  r.y = r.y_unlocked = y_from;
  const double lock_distance = options.lock_fraction * cell.activation_distance();
  double step = std::min(options.initial_step, s_to - s_from);
  CellSolveOptions ramp_solve = options.solve;
  ramp_solve.max_iterations = std::min(ramp_solve.max_iterations, 50);
  Vector tangent;
  double tangent_at = -1.0;
  while (r.s < s_to) {
    const double s_try = std::min(r.s + step, s_to);
    const double k_old = sign * r.s, k_new = sign * s_try;
    const Vector x_old = curved.full_state(r.y, k_old);
    if (tangent_at != r.s) {
      tangent = curved_tangent(curved, r.y, k_old, sign);
      tangent_at = r.s;
    }
    Vector y_pred = r.y;
    double alpha = 0.0;
    const auto consider = [&](const Vector& y_candidate) {
      if (alpha == 1.0) return;
      const double a = contact_max_step(cell, x_old, curved.full_state(y_candidate, k_new) - x_old);
      if (a > alpha) {
        alpha = a;
        y_pred = y_candidate;
      }
    };
    if (!tangent.isZero()) consider(r.y + (s_try - r.s) * tangent);
    consider(curved.bend_masters(r.y, k_old, k_new));
    consider(r.y);
    const double s_new = r.s + alpha * (s_try - r.s);
    if (!(s_new - r.s > options.min_step)) {
      r.stalled = true;
      r.message = "the ramp stalled at s = " + std::to_string(r.s) + " (CCD admits no further step)";
      return r;
    }
    const CellSolveResult solve =
        curved_newton(curved, sign * s_new, r.y + alpha * (y_pred - r.y), ramp_solve);
    ++solves;
    if (!solve.converged) {
      step *= 0.5;
      if (step < options.min_step) {
        r.stalled = true;
        r.message = "Newton failed at s = " + std::to_string(s_new) + ": " + solve.message;
        return r;
      }
      continue;
    }
    const double d = smallest_distance(cell, curved.full_state(solve.y, sign * s_new), cell.activation_distance());
    if (d <= lock_distance) {
      r.locked = true;
      r.s_unlocked = r.s;
      r.y_unlocked = r.y;
      r.s = s_new;
      r.y = solve.y;
      return r;
    }
    r.s = s_new;
    r.y = solve.y;
    if (alpha == 1.0) step = std::min(options.initial_step, 2.0 * step);
  }
  return r;
}

// The critical pair's distance and its gradient in the full state.
double curved_pair_distance(const PeriodicRigidCell& cell, const Vector& x, int a, int b, Vector* gradient,
                            bool& degenerate) {
  const Vector p = cell.radii_parameters();
  const tori::TorusDistance d = tori::torus_distance(cell.contact().pose(a, x, p), cell.contact().pose(b, x, p),
                                                     gradient != nullptr, cell.contact().options().distance);
  degenerate = d.degenerate;
  if (gradient) {
    *gradient = Vector::Zero(x.size());
    gradient->segment<6>(6 * a) = d.gradient.segment<6>(0);
    gradient->segment<6>(6 * b) = d.gradient.segment<6>(6);
  }
  return d.distance;
}

// Newton on (y, s): f = dE/dy = 0, d_ab = target (limit_sensitivity.hpp's bordered system).
bool curved_refine(const SingleCurvatureCell& curved, double sign, double target, int a, int b, Vector& y, double& s) {
  const PeriodicRigidCell& cell = curved.cell();
  const double d_hat = cell.activation_distance();
  for (int it = 0; it <= 40; ++it) {
    const SingleCurvatureCell::Reduced c = curved.reduce(y, sign * s, true, HessianMode::exact);
    Vector grad_d;
    bool degenerate = false;
    if (!std::isfinite(c.energy)) return false;
    const double distance = curved_pair_distance(cell, c.x, a, b, &grad_d, degenerate);
    if (degenerate) return false;
    const double residual = c.gradient.lpNorm<Eigen::Infinity>(), constraint = std::abs(distance - target);
    if (residual <= 1e-10 && constraint <= 1e-12 * d_hat) return true;
    if (it == 40) return residual <= 1e-7 && constraint <= 1e-9 * d_hat;
    const Vector fs = sign * c.mixed;
    const Vector cy = c.jacobian.transpose() * grad_d;
    const double cs = sign * grad_d.dot(c.curvature_derivative);
    const Vector lambda = curved_pseudo_solve(c.hessian, cy);
    const double ds = (-(distance - target) + lambda.dot(c.gradient)) / (cs - lambda.dot(fs));
    const Vector dy = -curved_pseudo_solve(c.hessian, c.gradient + fs * ds);
    double alpha = 1.0;
    for (int ls = 0; ls < 30; ++ls, alpha *= 0.5)
      if (smallest_distance(cell, curved.full_state(y + alpha * dy, sign * (s + alpha * ds)), d_hat) > 0.0) break;
    y += alpha * dy;
    s += alpha * ds;
  }
  return false;
}

}  // namespace

CellSolveResult solve_single_curvature_equilibrium(const SingleCurvatureCell& cell, double kappa, const Vector& y_start,
                                                   const CellSolveOptions& options) {
  try {
    return curved_newton(cell, kappa, y_start, options);
  } catch (const std::runtime_error& e) {  // a degenerate (coaxial) pair in contact
    CellSolveResult result;
    result.y = y_start;
    result.message = e.what();
    return result;
  }
}

LimitPoint find_single_curvature_limit(const SingleCurvatureCell& curved, const Vector& y_rest,
                                       const LimitOptions& options, double sign) {
  const PeriodicRigidCell& cell = curved.cell();
  LimitPoint out;
  out.angle = curved.angle();
  int solves = 0;
  const auto finish = [&](double s, const Vector& y) {
    out.strain = s;
    out.y = y;
    out.deformation = curved.deformation(sign * s);
    const Vector x = curved.full_state(y, sign * s);
    out.min_distance = smallest_distance(cell, x, std::numeric_limits<double>::infinity());
    out.active = active_pairs(cell, x);
    out.solves = solves;
  };
  RampResult first;
  try {
    first = curved_ramp(curved, sign, y_rest, 0.0, options.max_strain, options, solves);
  } catch (const std::runtime_error& e) {
    out.status = e.what();
    out.y = y_rest;
    return out;
  }
  if (!first.locked) {
    finish(first.s, first.y);
    out.status = first.stalled ? first.message : "free up to max_strain";
    return out;
  }
  double s_lo = first.s_unlocked, s_hi = first.s;
  Vector y_lo = first.y_unlocked, y_hi = first.y;
  bisect_lock(s_lo, y_lo, s_hi, y_hi, options.tolerance, [&](const Vector& y, double from, double to) {
    return curved_ramp(curved, sign, y, from, to, options, solves);
  });
  out.locked = true;
  out.bracket = s_hi - s_lo;
  // The critical pair: the closest pair within d_hat at the locked end.
  const Vector x_hi = curved.full_state(y_hi, sign * s_hi);
  double best = std::numeric_limits<double>::infinity();
  for (const tori::TorusPair& pair : contact_close_pairs(cell, x_hi, cell.activation_distance(), false))
    if (pair.distance.distance < best) {
      best = pair.distance.distance;
      out.critical_a = pair.a;
      out.critical_b = pair.b;
    }
  double s = s_hi;
  Vector y = y_hi;
  if (options.refine && out.critical_a >= 0) {
    double s_ref = s_hi;
    Vector y_ref = y_hi;
    bool ok = false;
    try {
      ok = curved_refine(curved, sign, options.lock_fraction * cell.activation_distance(), out.critical_a,
                         out.critical_b, y_ref, s_ref);
    } catch (const std::runtime_error&) {
      ok = false;
    }
    if (ok && s_ref >= s_lo - options.tolerance && s_ref <= s_hi + options.tolerance) {
      out.refined = true;
      s = s_ref;
      y = y_ref;
    }
  }
  finish(s, y);
  out.status = "locked";
  return out;
}

}  // namespace tailor::interlocking
