#pragma once
// The strain-space boundary of a periodic rigid cell (docs/interlocking.md): along a load path
//   F(s) = I + F_offset + s G,  s >= 0,
// (G the path's direction: diag(cos t, sin t) for a direction t of the (eps_xx, eps_yy) plane,
// d d^T for a uniaxial stretch along d; F_offset a fixed mixed state, e.g. a shear) the strain s
// is ramped with Newton + CCD (cell_equilibrium.hpp) until the cell locks.
//
// Lock-up criterion: the equilibrium's smallest pair distance falls to lock_fraction x d_hat
// (default 1/2). Before lock-up the elements have room and the equilibrium keeps every gap near
// or above d_hat (the barrier is zero beyond d_hat); once locked, further strain can only
// compress the barrier, so the smallest gap falls monotonically. In forces: the criterion is the
// cell's reaction reaching the force of one pair at lock_fraction d_hat -- a reaction threshold
// that, unlike a threshold on the stress, does not depend on the barrier stiffness kappa (the
// equilibrium placements do not). The limit converges to the geometric one as d_hat -> 0; a
// chain's is 2(R - r) - lock_fraction d_hat between centres.
//
// A mixed state's F_offset is reached first by the same ramp along I + t F_offset, t in [0, 1]
// (a path whose offset locks is reported as inadmissible). Ramp: steps of initial_step in s; each step predicts the masters by the affine map of the
// macro step (about the anchor), and the CCD of the contact term along the straight path from
// the last equilibrium to the prediction caps the step (so no state is ever intersecting); a
// Newton failure halves the step. Bisection on the criterion then brackets the limit to
// `tolerance` (in s), each midpoint reached by the same ramp from the bracket's unlocked end;
// finally Newton on the augmented system (equilibrium and d_critical = lock_fraction d_hat, in
// (y, s); limit_sensitivity.hpp) locates it to round-off (`refined`).
#include <string>
#include <utility>
#include <vector>

#include "forward/interlocking/cell_equilibrium.hpp"

namespace tailor::interlocking {

struct LoadPath {
  Eigen::Matrix2d direction = Eigen::Matrix2d::Identity();  // G
  Eigen::Matrix2d offset = Eigen::Matrix2d::Zero();          // F_offset
  double angle = 0.0;                                        // the sample's angle t [rad] (reports)
  Eigen::Matrix2d deformation(double s) const { return Eigen::Matrix2d::Identity() + offset + s * direction; }
};
// G = diag(cos t, sin t): a ray of the (eps_xx, eps_yy) plane.
LoadPath principal_path(double angle);
// G = d d^T, d = (cos t, sin t): uniaxial stretch along d (lateral and shear strain held at 0).
LoadPath uniaxial_path(double angle);

struct LimitOptions {
  double initial_step = 0.02;     // in s
  double max_strain = 1.0;        // s beyond which the path counts as never locking
  double tolerance = 1e-4;        // bisection bracket in s
  double lock_fraction = 0.5;     // the criterion above
  double min_step = 1e-9;         // a ramp step below this is a stall
  bool refine = true;             // the augmented Newton after the bisection
  CellSolveOptions solve;
};

struct ActivePair {
  int body_a = 0, body_b = 0;  // bodies of the cell (masters first, then images)
  std::string label;           // "i-j(a,b)": master i against master j shifted by (a, b)
  double distance = 0.0;
  Eigen::Vector3d force_on_b = Eigen::Vector3d::Zero();  // [unit pair force]
};

struct LimitPoint {
  double angle = 0.0;
  bool locked = false;        // false: no lock-up up to max_strain
  bool refined = false;       // located to round-off by the augmented Newton
  double strain = 0.0;        // s at the limit (max_strain when not locked)
  double bracket = 0.0;       // width of the final bisection bracket
  Eigen::Matrix2d deformation = Eigen::Matrix2d::Identity();  // F at the limit
  Vector y;                   // the cell's free DOFs at the limit
  double min_distance = 0.0;  // smallest pair distance there
  int critical_a = -1, critical_b = -1;  // bodies of the pair that meets the criterion
  std::vector<ActivePair> active;        // pairs within d_hat
  int solves = 0;                        // Newton solves spent
  std::string status;                    // "locked", "free up to max_strain", or why it stopped
};

// The limit along one path, starting from the equilibrium y_rest at s = 0.
LimitPoint find_limit(const PeriodicRigidCell& cell, const LoadPath& path, const Vector& y_rest,
                      const LimitOptions& options = {});

// The equilibrium at F = I from the cell's rest placement (throws std::runtime_error if Newton
// fails there).
Vector rest_equilibrium(const PeriodicRigidCell& cell, const CellSolveOptions& options = {});

// Limits along every path (each from y_rest).
std::vector<LimitPoint> strain_space_boundary(const PeriodicRigidCell& cell, const std::vector<LoadPath>& paths,
                                              const LimitOptions& options = {});

// The pairs within d_hat at x with their forces, labelled by periodic pair.
std::vector<ActivePair> active_pairs(const PeriodicRigidCell& cell, const Vector& x);

// One ramp of a lock-up search: equilibria from s_from towards s_to, stopped at the first locked
// state (strain_boundary.cpp for in-plane paths, single_curvature_limit.cpp for curvature).
struct RampResult {
  bool locked = false;
  bool stalled = false;
  double s = 0.0;  // where it stopped: s_to, the first locked strain, or the stall
  Vector y;
  double s_unlocked = 0.0;  // the last unlocked equilibrium before a lock
  Vector y_unlocked;
  std::string message;
};

// Bisection of a bracket [s_lo, s_hi] (last unlocked, first locked state, with their equilibria)
// down to `tolerance`: ramp(y, s_from, s_to) -> RampResult ramps from the unlocked end to the
// midpoint. Narrows the bracket in place; stops early when a ramp stalls.
template <class Ramp>
void bisect_lock(double& s_lo, Vector& y_lo, double& s_hi, Vector& y_hi, double tolerance, Ramp&& ramp) {
  while (s_hi - s_lo > tolerance) {
    const double mid = 0.5 * (s_lo + s_hi);
    RampResult r = ramp(y_lo, s_lo, mid);
    if (r.locked) {
      s_lo = r.s_unlocked;
      y_lo = std::move(r.y_unlocked);
      s_hi = r.s;
      y_hi = std::move(r.y);
    } else if (r.stalled) {
      break;
    } else {
      s_lo = mid;
      y_lo = std::move(r.y);
    }
  }
}

}  // namespace tailor::interlocking
