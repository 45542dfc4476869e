#pragma once
// Rest-shape design by inverse statics (docs/rods.md, "Rest-shape design by inverse statics").
//
// With the state held at the drawn shape x_d, the equilibrium condition of the free DOFs
//   r(p) = S^T (dE/dx (x_d, p) - f_ext) = 0
// is LINEAR in the rest curvatures and rest twists: the bending and twisting energies are
// quadratic in (kappa - kappabar) and (m - mbar) (Bergou 2008 eqs. 4-5), so dE/dx is affine in
// them. A strand's rest shape is therefore one small least-squares solve with the exact
// Jacobian dr/dz = S^T (d2E/dxdp) (dp/dz) (the mixed block the rod terms already provide),
// instead of an optimization whose every evaluation is a Newton solve. Rest lengths, when they
// are designed as well, enter r nonlinearly but weakly (through l/L in the stretching force and
// 1/(L_{i-1} + L_i) in the bending and twisting stencils): the same step is then Gauss-Newton on
// r(z) = 0, iterated to its round-off floor (quadratic convergence; two or three steps).
//
// The result is accepted only if it is what the optimizer would have found:
//   - the residual at the drawn shape is at its round-off floor, eps ||H||_inf (1 + ||x||_inf)
//     (the estimate of forward/solve/newton.hpp) times a safety factor of 10, and
//   - the drawn shape is a stable equilibrium: the Hessian on the free DOFs is positive definite,
//     checked by a sparse LDL^T whose pivots are all positive (Sylvester's law of inertia: the
//     pivots' signs are the eigenvalues' signs).
// Otherwise the caller falls back to the optimizer (problems/rods/rod_inverse.cpp).
//
// Design variables z are those of the scene's parameterization: rest curvatures and twists
// as they are [rad], rest lengths as z = log(L / L0). Each step solves the normal equations of
// the column-scaled Jacobian with a shift of 1e-13 (directions the equilibrium does not see stay
// put); the rest length of a clamped edge, which only trades off against its neighbouring
// stencils' rest curvature, is left as drawn. The Tikhonov weight of the scene is not used:
// every exact solution has zero misfit.
#include <string>
#include <vector>

#include "forward/core/model.hpp"

namespace tailor {

struct RodInverseSpec;
struct RodSceneSpec;
struct RodInverseProblem;

// The stability check on the exact Hessian of the free DOFs at (expand(y), p): LDL^T pivots
// (fill-reducing order, no pivoting; positive pivots <=> positive definite) and the residual's
// round-off floor eps ||H||_inf (1 + ||x||_inf).
struct RodStability {
  double smallest_pivot = 0.0, largest_pivot = 0.0;
  int nonpositive_pivots = 0;  // 1 as well when the factorization met a zero pivot
  double residual_floor = 0.0;
  bool stable() const { return nonpositive_pivots == 0; }
};
RodStability rod_stability(const Model& model, const Vector& y, const Vector& p);

// Empty when inverse statics applies to the problem, else why not: the design must include
// rest_curvature and consist of rest_curvature, rest_twist and per-edge rest_length only, the
// target must be the drawn shape (every vertex, all three components, at its drawn position)
// and the scene must hold one rod.
std::string rod_inverse_statics_obstacle(const RodInverseSpec& spec, const RodSceneSpec& scene);

struct RodInverseStaticsResult {
  Vector z;                       // the design (the parameterization's variables)
  int steps = 0;                  // Gauss-Newton steps taken
  double residual_initial = 0.0;  // ||r|| at z0 [force units]
  double residual = 0.0;          // ||r|| at z
  std::vector<double> residuals;  // ||r|| at z0 and after each step taken
  bool at_round_off = false;      // residual <= 10 stability.residual_floor
  RodStability stability;         // at the drawn state and p(z)
  double seconds = 0.0;
  std::string message;  // what failed, or a summary when accepted
  bool accepted() const { return at_round_off && stability.stable(); }
};

// Solves r(z) = 0 at the drawn state from z0 and checks the result (see above). Does not touch
// the problem's functional (no forward solve). The problem must be applicable
// (rod_inverse_statics_obstacle empty); throws std::invalid_argument otherwise.
RodInverseStaticsResult solve_rod_inverse_statics(const RodInverseProblem& problem);

}  // namespace tailor
