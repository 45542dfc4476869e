#pragma once
// Bending limits of a periodic cell in single curvature (docs/interlocking.md, "Bending: periodic
// single curvature"): the curvature kappa = sign s along the cell's direction is ramped, the
// equilibrium y*(kappa) = argmin_y B(x(y, kappa)) (curved_periodicity.hpp) found by Newton with
// the PSD-projected reduced Hessian and a Levenberg shift, as cell_equilibrium.hpp does for
// the flat cell, until the same lock-up criterion (the smallest pair distance at
// lock_fraction d_hat) is met; bisection on s to `tolerance`; then Newton on the augmented
// system (f = dE/dy = 0, d_ab = lock_fraction d_hat) in (y, s), with f_s = sign d(dE/dy)/dkappa
// and c_s = sign grad d_ab . dx/dkappa from the map's exact derivatives, to round-off.
//
// Steps: each Newton step and each ramp prediction is capped by the contact term's CCD along the
// chord x(y) -> x(y + dy) in the full space (images included); the map is nonlinear in the
// masters' rotations, so the true path leaves the chord at second order in the step, and the
// line search accepts only states whose barrier is finite (an intersecting state has B = inf).
// Every reported state is re-checked independently (interpenetration_check.hpp) by the callers.
// Ramp predictions: the equilibrium path's tangent H dy/ds = -f_s (where pairs touch), the masters
// carried with the cylinder (SingleCurvatureCell::bend_masters), or held; the one CCD lets go
// furthest.
#include "forward/interlocking/curved_periodicity.hpp"
#include "forward/interlocking/strain_boundary.hpp"

namespace tailor::interlocking {

CellSolveResult solve_single_curvature_equilibrium(const SingleCurvatureCell& cell, double kappa, const Vector& y_start,
                                                   const CellSolveOptions& options = {});

// The limit along kappa = sign s, s >= 0, from the equilibrium y_rest at kappa = 0. The
// LimitPoint's strain is s (|kappa| at the limit), its angle the cell's, and its deformation
// I + kappa d d^T (sym(F) - I the curvature tensor, as for bending patches).
LimitPoint find_single_curvature_limit(const SingleCurvatureCell& cell, const Vector& y_rest,
                                       const LimitOptions& options = {}, double sign = 1.0);

}  // namespace tailor::interlocking
