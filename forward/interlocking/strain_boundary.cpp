// Ramping a macro strain until the cell locks (see strain_boundary.hpp).
#include "forward/interlocking/strain_boundary.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "forward/interlocking/limit_sensitivity.hpp"
#include "forward/rigid/rotation.hpp"

namespace tailor::interlocking {
namespace {

// y with the masters' translations mapped by the macro step F_new F_old^-1 about the anchor.
Vector affine_prediction(const PeriodicRigidCell& cell, const Vector& y, const Eigen::Matrix2d& F_old,
                         const Eigen::Matrix2d& F_new) {
  if (cell.spec().bending_patch) {
    // Free elements ride with the surface's local frame, as the rim does: an element at p = T_xy,
    // a height h along the normal (approximately (T_z - f(p)) n_z), moves with the frame's origin
    // (p, f(p)) + h n(p) and turns by Q_new Q_old^T (Q the smallest rotation taking e_z to n), so
    // that interlocked free and rim elements tilt together instead of the rim turning into them.
    const Eigen::Matrix2d K_old = PeriodicRigidCell::curvature(F_old), K_new = PeriodicRigidCell::curvature(F_new);
    Vector q = cell.full_state(y, F_old).head(6 * cell.num_elements());
    for (int i = 0; i < cell.num_elements(); ++i) {
      if (cell.spec().elements[static_cast<std::size_t>(i)].rim) continue;
      const Eigen::Vector2d p = q.segment<2>(6 * i);
      const Eigen::Vector2d slope = K_old * p;
      const double h = (q[6 * i + 2] - 0.5 * p.dot(slope)) / std::sqrt(1.0 + slope.squaredNorm());
      Eigen::Vector3d T_old, w_old, T_new, w_new;
      PeriodicRigidCell::surface_pose(K_old, Eigen::Vector3d(p.x(), p.y(), h), Eigen::Vector3d::Zero(), T_old, w_old);
      PeriodicRigidCell::surface_pose(K_new, Eigen::Vector3d(p.x(), p.y(), h), Eigen::Vector3d::Zero(), T_new, w_new);
      const Eigen::Vector3d w = q.segment<3>(6 * i + 3);
      q.segment<3>(6 * i) += T_new - T_old;
      q.segment<3>(6 * i + 3) = rigid::rotation_vector(
          rigid::rotation_matrix(w_new) * rigid::rotation_matrix(w_old).transpose() * rigid::rotation_matrix(w), w);
    }
    return cell.basis().topRows(6 * cell.num_elements()).transpose() * q;
  }
  const Eigen::Matrix2d A = F_new * F_old.inverse();
  Vector q = cell.master_state(y);
  const Eigen::Vector3d anchor = q.segment<3>(6 * cell.spec().anchor);
  for (int i = 0; i < cell.num_elements(); ++i) {
    const Eigen::Vector2d r = (q.segment<3>(6 * i) - anchor).head<2>();
    q.segment<2>(6 * i) = anchor.head<2>() + A * r;
  }
  return cell.basis().topRows(6 * cell.num_elements()).transpose() * q;
}

// Equilibria from (y, s_from) towards s_to in CCD-capped steps, stopping at the first state that
// meets the lock-up criterion.
RampResult ramp(const PeriodicRigidCell& cell, const LoadPath& path, const Vector& y_from, double s_from, double s_to,
                const LimitOptions& options, int& solves) {
  RampResult r;
  r.s = r.s_unlocked = s_from;
  r.y = r.y_unlocked = y_from;
  const double lock_distance = options.lock_fraction * cell.activation_distance();
  double step = std::min(options.initial_step, s_to - s_from);
  Vector tangent;
  std::optional<double> tangent_at;  // the s where `tangent` was taken
  // A ramp step's Newton starts from a prediction near its equilibrium (15-20 iterations on the
  // bending patches); one that has not converged in 50 is stalling along near-null modes (seen
  // running to 200 iterations at residuals of 1e-8) and is cheaper retried from a halved step.
  CellSolveOptions ramp_solve = options.solve;
  ramp_solve.max_iterations = std::min(ramp_solve.max_iterations, 50);
  while (r.s < s_to) {
    const double s_try = std::min(r.s + step, s_to);
    const Eigen::Matrix2d F_old = path.deformation(r.s), F_new = path.deformation(s_try);
    const Vector x_old = cell.full_state(r.y, F_old);
    // Predictions: the equilibrium path's tangent (where pairs touch), the masters moved
    // affinely (patches: riding with the surface), or held; the one CCD lets go furthest. Without
    // the tangent, elements sliding along each other in contact are predicted to close their
    // gaps (~d_hat), and CCD then admits only a fraction of that gap per step.
    if (!tangent_at || *tangent_at != r.s) {
      tangent = equilibrium_tangent(cell, path, r.y, r.s);
      tangent_at = r.s;
    }
    Vector y_pred = r.y;
    double alpha = 0.0;
    const auto consider = [&](const Vector& y_candidate) {
      if (alpha == 1.0) return;
      const double a = contact_max_step(cell, x_old, cell.full_state(y_candidate, F_new) - x_old);
      if (a > alpha) {
        alpha = a;
        y_pred = y_candidate;
      }
    };
    if (!tangent.isZero()) consider(r.y + (s_try - r.s) * tangent);
    consider(affine_prediction(cell, r.y, F_old, F_new));
    consider(r.y);
    const double s_new = r.s + alpha * (s_try - r.s);
    if (!(s_new - r.s > options.min_step)) {
      r.stalled = true;
      r.message = "the ramp stalled at s = " + std::to_string(r.s) + " (CCD admits no further step)";
      return r;
    }
    const Vector y_guess = r.y + alpha * (y_pred - r.y);  // the straight path is linear in s
    const CellSolveResult solve = solve_cell_equilibrium(cell, path.deformation(s_new), y_guess, ramp_solve);
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
    const double d = smallest_distance(cell, cell.full_state(solve.y, path.deformation(s_new)),
                                       cell.activation_distance());
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

// The pair of least distance at x (bodies), -1 when none within d_hat.
std::pair<int, int> closest_pair(const PeriodicRigidCell& cell, const Vector& x) {
  double best = std::numeric_limits<double>::infinity();
  std::pair<int, int> out{-1, -1};
  for (const tori::TorusPair& pair : contact_close_pairs(cell, x, cell.activation_distance(), false))
    if (pair.distance.distance < best) {
      best = pair.distance.distance;
      out = {pair.a, pair.b};
    }
  return out;
}

}  // namespace

LoadPath principal_path(double angle) {
  LoadPath p;
  p.direction = Eigen::Vector2d(std::cos(angle), std::sin(angle)).asDiagonal();
  p.angle = angle;
  return p;
}

LoadPath uniaxial_path(double angle) {
  LoadPath p;
  const Eigen::Vector2d d(std::cos(angle), std::sin(angle));
  p.direction = d * d.transpose();
  p.angle = angle;
  return p;
}

std::vector<ActivePair> active_pairs(const PeriodicRigidCell& cell, const Vector& x) {
  std::vector<ActivePair> out;
  for (const tori::TorusPairForce& f : contact_pair_forces(cell, x)) {
    ActivePair a;
    a.body_a = f.a;
    a.body_b = f.b;
    a.label = cell.pair_label(f.a, f.b);
    a.distance = f.distance;
    a.force_on_b = f.force_on_b;
    out.push_back(a);
  }
  return out;
}

Vector rest_equilibrium(const PeriodicRigidCell& cell, const CellSolveOptions& options) {
  const CellSolveResult r =
      solve_cell_equilibrium(cell, Eigen::Matrix2d::Identity(), cell.rest_free_state(), options);
  if (!r.converged) throw std::runtime_error("periodic cell: no equilibrium at rest: " + r.message);
  return r.y;
}

LimitPoint find_limit(const PeriodicRigidCell& cell, const LoadPath& path, const Vector& y_rest,
                      const LimitOptions& options) {
  LimitPoint out;
  out.angle = path.angle;
  int solves = 0;
  // A mixed state's fixed offset is reached first, by the same ramp along F = I + t F_offset,
  // t in [0, 1] (it must not lock on the way).
  Vector y_start = y_rest;
  if (!path.offset.isZero()) {
    LoadPath to_offset;
    to_offset.direction = path.offset;
    const RampResult pre = ramp(cell, to_offset, y_rest, 0.0, 1.0, options, solves);
    if (pre.locked || pre.stalled) {
      out.status = "the path's fixed offset is not admissible (" +
                   (pre.locked ? "locks at t = " + std::to_string(pre.s) : pre.message) + ")";
      out.y = pre.y;
      out.deformation = to_offset.deformation(pre.s);
      out.solves = solves;
      return out;
    }
    y_start = pre.y;
  }
  RampResult first = ramp(cell, path, y_start, 0.0, options.max_strain, options, solves);
  if (!first.locked) {
    out.strain = first.s;
    out.y = first.y;
    out.deformation = path.deformation(first.s);
    out.status = first.stalled ? first.message : "free up to max_strain";
    out.solves = solves;
    const Vector x = cell.full_state(out.y, out.deformation);
    out.min_distance = smallest_distance(cell, x, std::numeric_limits<double>::infinity());
    out.active = active_pairs(cell, x);
    return out;
  }
  double s_lo = first.s_unlocked, s_hi = first.s;
  Vector y_lo = first.y_unlocked, y_hi = first.y;
  bisect_lock(s_lo, y_lo, s_hi, y_hi, options.tolerance, [&](const Vector& y, double from, double to) {
    return ramp(cell, path, y, from, to, options, solves);
  });
  out.locked = true;
  out.bracket = s_hi - s_lo;
  out.strain = s_hi;
  out.y = y_hi;
  const auto [a, b] = closest_pair(cell, cell.full_state(y_hi, path.deformation(s_hi)));
  out.critical_a = a;
  out.critical_b = b;
  if (options.refine && a >= 0) {
    const RefineResult refined = refine_limit(cell, path, options.lock_fraction * cell.activation_distance(), a, b,
                                              y_hi, s_hi);
    // Accept the refined limit only inside the bracket (a far jump is another branch).
    if (refined.converged && refined.strain >= s_lo - options.tolerance && refined.strain <= s_hi + options.tolerance) {
      out.refined = true;
      out.strain = refined.strain;
      out.y = refined.y;
    }
  }
  out.deformation = path.deformation(out.strain);
  const Vector x = cell.full_state(out.y, out.deformation);
  out.min_distance = smallest_distance(cell, x, std::numeric_limits<double>::infinity());
  out.active = active_pairs(cell, x);
  out.solves = solves;
  out.status = "locked";
  return out;
}

std::vector<LimitPoint> strain_space_boundary(const PeriodicRigidCell& cell, const std::vector<LoadPath>& paths,
                                              const LimitOptions& options) {
  const Vector y_rest = rest_equilibrium(cell, options.solve);
  std::vector<LimitPoint> out;
  for (const LoadPath& path : paths) out.push_back(find_limit(cell, path, y_rest, options));
  return out;
}

}  // namespace tailor::interlocking
