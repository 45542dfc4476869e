#pragma once
// The distance between two tori when either tube is elliptic (r1 != r, torus.hpp; docs/tori.md).
//
// An elliptic tube is not the set of points within one radius of the core, so the core-circle
// reduction of torus_distance.hpp does not hold. Instead, with S_a, S_b the world surface points
// (torus.hpp's V(u, v) moved by T + Q(w)) and u = (u_a, v_a, u_b, v_b),
//   d^2 = min_u f,   f = |S_a(u_a, v_a) - S_b(u_b, v_b)|^2,
// the distance of two disjoint solids (neither inside the other). The global minimum: both
// surfaces sampled on (u, v) grids, every pair of samples compared, Newton on all four
// parameters (the Hessian's eigenvalues floored, backtracking on f) from the pairs at the
// lowest local minima over a's samples, each run ending with plain Newton steps on f_u = 0 while
// they shrink |f_u| (f is flat at the minimum, a decrease of f resolves u only to ~sqrt(eps)).
//
// Overlap: the implicit function of b's solid, g_b (torus.hpp; < 0 inside), on a's samples and
// a's closest point, then minimized over a's surface (Newton in (u_a, v_a)) from there; the same
// with the roles exchanged. Any negative value: the solids overlap (surfaces crossing, or one
// inside the other), reported as overlapping with distance = -max(-g min(r, r1) / 2) < 0 (g ~ 2
// (signed distance) / r near a circular surface) and no derivatives.
//
// Derivatives by the implicit function theorem as in the circular case: with y the other
// variables (T_a, w_a, T_b, w_b, R_a, r_a, r1_a, R_b, r_b, r1_b) and f_u = 0 at the minimizer,
//   d(d^2)/dy = f_y,   d2(d^2)/dy2 = f_yy - f_yu f_uu^-1 f_uy,
// then d = sqrt(d^2); f's derivatives in (u, y) from Dual2<22>. For a circular torus of the pair
// its r1 is the same jet variable as its r (r moves both semi-axes). Unlike the circular case
// f_uu has an eigenvalue of order d (both points sliding together along the common tangent
// plane), so the derivatives lose about eps R^2 / d of relative accuracy as d -> 0, and pairs
// with d below ~1e-9 R^2 of that eigenvalue floor are reported degenerate.
#include <Eigen/Core>

#include "forward/tori/torus_distance.hpp"

namespace tailor::tori {

// The distance of tori a and b by the four-parameter surface minimization, for any shapes
// (torus_distance() calls it when either is elliptic); with `derivatives` the gradient and
// Hessian in the 16 pair variables and the gradient in r1 (axial_gradient).
TorusDistance elliptic_torus_distance(const TorusPose& a, const TorusPose& b, bool derivatives,
                                      const DistanceOptions& options = {});

// A point V(u, v) of a torus's surface in the world.
Eigen::Vector3d surface_point(const TorusPose& pose, double u, double v);

// The implicit function g of the solid torus (torus.hpp) at a world point: < 0 inside.
double implicit_value(const TorusPose& pose, const Eigen::Vector3d& x);

}  // namespace tailor::tori
