#pragma once
// The lock-up state as the solution of an augmented system, and the exact derivative of the
// limit by the implicit function theorem (docs/interlocking.md, "Derivatives of a limit").
//
// On a load path F(s) (strain_boundary.hpp), the limit (y*, s*) solves
//   f(y, s, p) = S^T dB/dx (x0(F(s), L) + S y, p) = 0        (equilibrium, n equations)
//   c(y, s, p) = d_ab(x, p) - lock_fraction d_hat = 0          (the critical pair a, b)
// with p the master radii (R_i, r_i) and the lattice matrix L. With H = df/dy (the exact
// reduced Hessian), f_s = S^T H_x dx/ds, c_y = S^T grad_x d_ab, c_s = grad_x d_ab . dx/ds
// (dx/ds = dx0/ds, PeriodicRigidCell::offset_derivative: constant for periodic cells, the rim
// poses' first derivative in the curvature for bending patches; x0's second derivative enters
// neither the Newton matrix nor the implicit-function derivative, only f's second derivatives):
//   [H   f_s] [dy/dp]     [f_p]
//   [c_y c_s] [ds/dp] = - [c_p],
// so with the adjoint lambda = H^+ c_y^T (one solve for every parameter)
//   ds*/dp = -(c_p - lambda^T f_p) / (c_s - lambda^T f_s).
// H has exact null modes (a torus's spin about its own axis, elements out of contact) along
// which c_y, f_s and f_p vanish by symmetry; H^+ is the pseudo-inverse (eigenvalues below
// 1e-10 of the largest dropped), which is exact for such consistent right-hand sides.
// f_p for radii: S^T (d2B/dx dp_body) P (TorusContactTerm::add_mixed, P = radii_map());
// for L_kl: S^T H_x dx/dL_kl (the images move with L; zero for patches, which have no images);
// c_p from the pair distance's gradient.
#include <string>

#include "forward/interlocking/strain_boundary.hpp"

namespace tailor::interlocking {

struct RefineResult {
  bool converged = false;
  double strain = 0.0;
  Vector y;
  int iterations = 0;
  double residual = 0.0;    // ||f||_inf
  double constraint = 0.0;  // |c| [length]
  std::string message;
};

// Newton on (y, s) from (y_start, s_start), the critical pair (body_a, body_b) fixed.
RefineResult refine_limit(const PeriodicRigidCell& cell, const LoadPath& path, double target_distance,
                          int body_a, int body_b, const Vector& y_start, double s_start, int max_iterations = 40);

struct LimitGradient {
  Vector radii;             // ds*/d(R_0, r_0, ..., R_{N-1}, r_{N-1})
  Eigen::Matrix2d lattice;  // ds*/dL_kl
  double denominator = 0.0; // c_s - lambda^T f_s (how sharply the path locks; 0 would be a fold)
};

// At a refined limit (y, s) of `path` with critical pair (a, b).
LimitGradient limit_gradient(const PeriodicRigidCell& cell, const LoadPath& path, int body_a, int body_b,
                             const Vector& y, double s);

// The equilibrium path's tangent dy/ds at an equilibrium (y, s) of `path`: H dy/ds = -f_s, H the
// exact reduced Hessian (pseudo-inverse as above: no motion along its null modes), f_s =
// S^T H_x dx0/ds. Zero where no pair is within d_hat (then every nearby state is an equilibrium).
// The ramp's first-order predictor (strain_boundary.cpp): pairs in contact slide along each other
// instead of closing their gap.
Vector equilibrium_tangent(const PeriodicRigidCell& cell, const LoadPath& path, const Vector& y, double s);

// A copy of the cell's spec with master radii (R_i, r_i) and lattice L replaced (d_hat kept).
RigidCellSpec with_parameters(const RigidCellSpec& spec, const Vector& radii, const Eigen::Matrix2d& lattice);
// The master radii (R_0, r_0, ...) of a spec.
Vector master_radii(const RigidCellSpec& spec);

}  // namespace tailor::interlocking
