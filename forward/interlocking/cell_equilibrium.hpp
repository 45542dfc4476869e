#pragma once
// Static equilibrium of a periodic rigid cell at a macro deformation F (docs/interlocking.md):
//   y*(F) = argmin_y B(x0(F) + S y),   B the torus contact barrier (periodic_cell.hpp).
// There is no other energy: before the elements lock every intersection-free placement with all
// gaps >= d_hat is an equilibrium (B = 0), and the Hessian has null modes (a torus spinning
// about its own axis, elements out of contact). Newton therefore steps with the PSD-projected
// Hessian plus a Levenberg shift mu I (mu = regularization x (1 + max diagonal); 10^3 and 10^6
// times that where the step finds no decrease), the step
// capped by the contact term's CCD along the full-space path x + t S dy (masters and images
// move together), then backtracked on B (Armijo). Converged when ||S^T dB/dx||_inf <=
// force_tolerance (units: the force of one pair at d_hat / 2 is 1).
#include <functional>
#include <string>
#include <vector>

#include "forward/interlocking/periodic_cell.hpp"

namespace tailor::interlocking {

struct CellSolveOptions {
  int max_iterations = 200;
  double force_tolerance = 1e-9;  // [unit pair force]
  double regularization = 1e-9;   // mu / (1 + max |H_ii|)
  int max_line_search_steps = 40;
};

struct CellSolveResult {
  Vector y;
  bool converged = false;
  int iterations = 0;
  double residual = 0.0;       // ||S^T dB/dx||_inf at y
  double energy = 0.0;         // B at y
  std::string message;
};

// What one iteration of levenberg_newton needs at the reduced state y: the barrier B, its
// reduced gradient and a positive semidefinite reduced Hessian, the largest admissible fraction
// of a step dy (the contact term's CCD along the state's path), and B at y + alpha dy.
struct CellNewtonPoint {
  double energy = 0.0;
  Vector gradient;
  Matrix hessian;
  std::function<double(const Vector& dy)> max_step;
  std::function<double(double alpha, const Vector& dy)> energy_along;
};

// The Newton loop described above, on any reduced parametrization of the cell (the planar one
// below; the screw-periodic one of single_curvature_limit.cpp): from y_start until the reduced
// gradient's largest entry is at most options.force_tolerance. The line search halves alpha
// while alpha > smallest_step.
CellSolveResult levenberg_newton(const Vector& y_start, const CellSolveOptions& options, double smallest_step,
                                 const std::function<CellNewtonPoint(const Vector& y)>& point_at);

// From y_start (which must be intersection-free at F: B finite). Throws nothing; a failure is
// reported in `converged` / `message`.
CellSolveResult solve_cell_equilibrium(const PeriodicRigidCell& cell, const Eigen::Matrix2d& F,
                                       const Vector& y_start, const CellSolveOptions& options = {});

// B, S^T dB/dx and the dense reduced Hessian S^T H S (exact or projected) at x = x0(F) + S y.
struct ReducedContact {
  double energy = 0.0;
  Vector gradient;     // S^T dB/dx
  Vector full_gradient;  // dB/dx
  Matrix hessian;      // S^T H S
  SparseMatrix full_hessian;  // H (both triangles)
};
ReducedContact reduced_contact(const PeriodicRigidCell& cell, const Vector& x, bool hessian,
                               HessianMode mode = HessianMode::exact);

// The smallest pair distance at x (infinity when no pair is within `range`).
double smallest_distance(const PeriodicRigidCell& cell, const Vector& x, double range);

// B at x alone (+infinity for an intersecting state).
double contact_energy(const PeriodicRigidCell& cell, const Vector& x);

// The contact term's CCD step bound along x + t dx, t in [0, 1] (TorusContactTerm::max_step:
// conservative advancement on the torus distance), over the broad phase's candidates.
double contact_max_step(const PeriodicRigidCell& cell, const Vector& x, const Vector& dx);

// The pairs within `range` (finite: through the broad phase) with their distances, and the
// forces of the pairs within d_hat (as TorusContactTerm::close_pairs / pair_forces; with a
// bending patch these include rim-rim pairs, which the contact term skips).
std::vector<tori::TorusPair> contact_close_pairs(const PeriodicRigidCell& cell, const Vector& x, double range,
                                                 bool derivatives);
std::vector<tori::TorusPairForce> contact_pair_forces(const PeriodicRigidCell& cell, const Vector& x);

// With spec().broad_phase these evaluate the barrier of TorusContactTerm (same pair energy,
// same pair order, so the same sums) over PeriodicRigidCell::candidate_pairs, and the Hessian
// over the pairs within d_hat only; without it they call the contact term (every pair).

}  // namespace tailor::interlocking
