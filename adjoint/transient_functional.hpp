#pragma once
// TransientFunctional: the reduced functional of a time-dependent inverse problem,
//   J(z) = sum_{n=0..N} J_n(x_n, v_n, p),  P = phi(z) = [p; x_0 (optional); v_0 (optional)],
// where the states follow N implicit time steps (forward/dynamics/time_integrator.hpp), each
// the minimiser of an incremental potential Pi_{n+1}(x; history, p). The gradient comes from
// the discrete adjoint of the steps (docs/methods.md section 2, "backwards in time"): going from
// step N down to 1, with the adjoints (xb, vb, fb) of the state after the step,
//   H_{n+1} lambda = S^T (xb + vb / kappa + c M fb)          (H: exact reduced step Hessian)
//   x~b = c M (Lambda - fb),  x^b = -vb / kappa + H_D Lambda,  gb = Lambda - fb   (Lambda = S lambda)
//   pb -= (d2 Pi/dx dp)^T Lambda - c (d2 Pi_inertia/dx dp)^T fb    ... (see the .cpp)
// and the history adjoints collect x~b, x^b and gb through the scheme's linear maps (StepMap);
// Newmark's start g_0 = -dPi_0/dx(x_0) adds one Hessian and one mixed product at the end. The
// step residuals are differentiated exactly, so the gradient is exact up to the Newton and
// linear tolerances (checked by Taylor tests).
//
// Linear solves reuse factorizations. A backward step's Hessian is solved by conjugate
// gradients preconditioned with the exact LL^T factor nearest in time: Newton's last
// factorization (made at some iterate of a known step of the forward pass, or earlier) or the
// last one the backward pass made itself (consecutive step Hessians differ by O(h)). CG
// refines to linear_relative_tolerance on the exact Hessian of the step, so the kept factor is
// only a preconditioner and the gradient stays exact; a step is factorized afresh only when CG
// does not converge in max_cg_iterations (the fresh factor then preconditions the next steps).
// A constant Hessian (linear materials, inertia, Rayleigh damping with its kept stiffness) is
// Newton's kept factor itself: no assembly, no factorization, one back-solve per step.
//
// Step Hessians from the forward pass: Newton assembles the exact Hessian at the converged state
// of each step for its convergence test (NewtonSolver::hessian()). The forward pass keeps a copy
// of its values (the pattern is shared) while their total stays within
// stored_hessian_megabytes, and the backward step at that state solves with the copy instead of
// assembling it again: the same matrix bit for bit, one assembly fewer per step. Memory: nnz of
// the reduced Hessian's upper triangle, 8 bytes each per step (5.4 MB per step for the 58k-tet
// cantilever of dynamics_bench, against about 1 MB for its state): the default of 512 MB holds
// about 95 such steps; the steps beyond it are assembled in the backward pass.
// Projected or shifted Hessians (indefinite steps) are never kept.
//
// With the integrator's NewtonOptions::linear_solver set (e.g. PETSc's KSP,
// forward/solve/linear_solver.hpp) every backward step's exact Hessian is set up on that
// solver instead and solved to linear_relative_tolerance; no CHOLMOD factor is made or reused.
// Terms with low-rank Hessian parts are refused there, as in Newton's steps.
//
// Memory: every state is stored by default. With checkpoint_interval = k > 1 only every k-th
// state (and the last segment) is kept and the states in between are recomputed segment by
// segment during the backward pass: about N/k + k states in memory for about N (1 - 1/k)
// recomputed steps.
#include "adjoint/parameterization.hpp"
#include "adjoint/reduced_functional.hpp"
#include "forward/dynamics/time_integrator.hpp"
#include "objectives/trajectory_objective.hpp"

namespace tailor {

struct TransientFunctionalOptions {
  int steps = 100;
  int checkpoint_interval = 0;             // 0 or 1: store every state
  bool design_initial_positions = false;   // P gets x_0 (num_dofs entries) after p
  bool design_initial_velocities = false;  // P gets v_0 (num_dofs entries) after that
  bool reuse_factorizations = true;        // false: factorize every backward step
  // Upper bound of the forward pass's copies of converged step Hessians (see above); 0: none,
  // every backward step assembles its Hessian.
  double stored_hessian_megabytes = 512.0;
  // Of the CG solves preconditioned by a kept factor, and of every backward solve with the
  // integrator's NewtonOptions::linear_solver. The rule of StaticFunctionalOptions: the
  // gradient's relative error is at most about cond(H) times the adjoint's relative residual,
  // and the steps' states are held to the integrator's Newton tolerance (1e-10 relative by
  // default), so the adjoint is solved 100x tighter (1e-12): its error stays below the one the
  // states themselves put into the gradient, over every step of the backward pass.
  double linear_relative_tolerance = 1e-12;
  int max_cg_iterations = 20;
};

struct TransientStatistics {
  int steps = 0;
  int forward_steps = 0;      // Newton solves in the last evaluation (forward pass + recomputation)
  int recomputed_steps = 0;   // of those, recomputed during the backward pass
  int newton_iterations = 0;  // in the forward pass
  int stored_states_peak = 0;
  double stored_megabytes_peak = 0.0;
  int factorizations = 0;  // backward pass
  int cg_solves = 0, cg_iterations = 0;
  int kept_factor_solves = 0;  // backward steps solved with Newton's kept factor of a constant Hessian
  // Of the last backward pass (kept by later value() calls): the steps solved with
  // NewtonOptions::linear_solver, their summed iterations, and the last one (its
  // relative_tolerance is linear_relative_tolerance).
  int linear_solver_solves = 0;
  long long linear_solver_iterations = 0;
  LinearSolveStats last_linear_solve;
  double forward_seconds = 0.0;  // forward pass
  double adjoint_seconds = 0.0;  // backward pass, including recomputation
  // Sparse Cholesky work (numeric factorizations, right-hand sides back-solved) of the forward
  // pass (Newton) and of the backward pass (its own factor, Newton's as preconditioner or as
  // the kept factor of a constant Hessian, recomputation's Newton solves included).
  long forward_factorizations = 0, forward_back_solves = 0;
  long adjoint_numeric_factorizations = 0, adjoint_back_solves = 0;
  // Backward pass: step Hessians assembled there and taken from the forward pass's copies, the
  // copies' peak size, and where the time went (wall seconds: Hessian assembly, numeric
  // factorization, solves with CG and back-solves, parameter-derivative products and the other
  // adjoint updates, recomputation of checkpointed segments).
  int hessian_assemblies = 0, stored_hessians_used = 0;
  double stored_hessian_megabytes_peak = 0.0;
  double adjoint_assembly_seconds = 0.0, adjoint_factorization_seconds = 0.0, adjoint_solve_seconds = 0.0;
  double adjoint_products_seconds = 0.0, adjoint_recompute_seconds = 0.0;
  double adjoint_start_seconds =
      0.0;  // Newmark: the terms of g_0 = -dPi_0/dx(x_0) (a Hessian and a mixed product)
  // Of the CG solves preconditioned by a kept factor: the largest relative residual of the
  // factor's plain solve (what the gradient would carry without CG's refinement).
  double max_preconditioner_residual = 0.0;
  double recompute_ratio() const { return steps ? static_cast<double>(recomputed_steps) / steps : 0.0; }
};

class TransientFunctional final : public ReducedFunctional {
 public:
  // The integrator (and its model) must outlive the functional. Initial positions and velocities
  // are the values used when they are not designed.
  TransientFunctional(TimeIntegrator& integrator, ParameterizationPtr parameterization,
                      TrajectoryObjectivePtr objective, Vector initial_positions, Vector initial_velocities,
                      TransientFunctionalOptions options = {});

  int size() const override { return parameterization_->num_design(); }
  double value(const Vector& z) override;
  double value_and_gradient(const Vector& z, Vector& gradient) override;

  // dL/dz of another trajectory objective L at the trajectory of z, by the same backward pass
  // (the forward pass is reused when z is the design evaluated last). With PositionCotangents
  // this is the trajectory's vector-Jacobian product. The functional's own objective is kept.
  Vector objective_gradient(const Vector& z, TrajectoryObjectivePtr other);

  // The trajectory's Jacobian-vector product: row n holds dx_n/dz dz (full DOF space) for the
  // states n = 0 ... N of z's trajectory, by one forward tangent pass over the steps
  // (transient_tangent.cpp; the transpose of the backward pass above, step by step). The
  // forward pass is reused when z is the design evaluated last. Refused (std::invalid_argument)
  // for damping whose coefficients lag the step's start state (ExampleDamping).
  Matrix trajectory_jvp(const Vector& z, const Vector& dz);

  // Size of P: |p| + num_dofs per designed initial condition.
  int num_extended_params() const;
  // The stored states of the last forward pass (all of them without checkpointing).
  const std::vector<DynamicState>& stored_states() const { return stored_; }
  const TransientStatistics& statistics() const { return statistics_; }

 private:
  struct Adjoint;  // adjoints of one DynamicState
  void forward(const Vector& z);
  void store(const DynamicState& state);
  // The states n0..n1 (inclusive) of the current trajectory, recomputed when necessary.
  std::vector<DynamicState> segment(int n0, int n1);
  void backward_step(const DynamicState& from, const DynamicState& to, Adjoint& adjoint, Vector& gradient_p);
  Vector solve_step(const Vector& rhs, int step);
  // H_{n+1}^{-1} rhs for the step that produced `to` (its terms configured), full DOF space,
  // by the solver the backward pass uses (release_stored: free the kept copy of H once used).
  Vector solve_step_hessian(const DynamicState& to, const Vector& rhs, bool release_stored);
  // The forward pass's copy of the converged Hessian of `step` into hessian_, if it kept one
  // (release: drop the copy afterwards).
  bool take_stored_hessian(int step, bool release = true);
  void keep_step_hessian(int step);
  Vector solve_with_linear_solver(LinearSolver& solver, const Vector& rhs, int step);
  void add_objective_gradient(const DynamicState& s, Adjoint& adjoint, Vector& gradient_p) const;
  struct Tangent;  // tangents of one DynamicState
  void tangent_step(const DynamicState& from, const DynamicState& to, const Vector& dp, Tangent& t);

  TimeIntegrator& integrator_;
  ParameterizationPtr parameterization_;
  TrajectoryObjectivePtr objective_;
  Vector x0_, v0_;
  TransientFunctionalOptions options_;
  // Evaluation state.
  bool have_state_ = false;
  Vector z_, p_, x_init_, v_init_;
  double value_ = 0.0;
  std::vector<DynamicState> stored_;  // all states, or the checkpoints
  std::vector<DynamicState> tail_;    // with checkpointing: the states after the last checkpoint
  // Backward pass.
  SparseMatrix hessian_;
  LowRankHessian low_rank_;  // of the step Hessian being solved
  SparseCholesky factor_;
  bool factor_analyzed_ = false, have_factor_ = false;
  int factor_step_ = -1;               // the step whose Hessian factor_ holds
  int newton_factor_step_ = -1;        // the step at whose iterates Newton last factorized (-1: unknown)
  std::vector<Vector> step_hessians_;  // by step: values of the converged exact Hessian (or empty)
  double step_hessian_megabytes_ = 0.0;
  TransientStatistics statistics_;
};

}  // namespace tailor
