#pragma once
// Newton's method with a backtracking line search on the total potential, for
//   y* = argmin_y E(x0 + S y, p),   i.e.  S^T dE/dx = 0.
//
// Convergence criterion (all norms are Euclidean norms of the reduced gradient S^T dE/dx,
// i.e. of the out-of-balance force in force units):
//   ||g_k|| <= relative_tolerance * ||g_0||      (relative to the initial residual), or
//   ||g_k|| <= absolute_tolerance                 (an absolute floor, default 0 = off), or
//   the last step was a full Newton step with ||dx||_inf <= step_tolerance * (1 + ||x||_inf)
//   and ||g_k|| <= sqrt(relative_tolerance) * ||g_0||: the iterate no longer changes in
//   floating point, so the residual has reached its round-off floor (which scales with the
//   stiffness times the coordinates and cannot be predicted by a fixed absolute number).
// A start that is already in equilibrium (||g_0|| = 0) converges at once.
//
// The round-off floor (docs/performance.md, "The round-off floor"). A residual computed in
// double precision cannot fall below the error of the forces it sums: positions are held to
// relative precision eps, so component i of the residual carries an error of about
//   f_i = eps * (1 + ||x||_inf) * sum_j |H_ij|       (force units),
// the row sum of the exact Hessian's absolute values times the size of the coordinates.
// residual_floor reports ||f||_2; the test is componentwise, w = max_i |g_i| / f_i (a residual
// component where f_i = 0, e.g. on a node of zero stiffness, is never at round-off), so that
// the round-off of a stiff part does not hide the load on a soft one. Newton stops at the
// floor (status round_off_floor, converged) when
//   - at the start, w <= 1 and the Newton step from it is below 100 eps (1 + ||x||_inf): a state
//     already in equilibrium to round-off (a start within its floor whose step is larger is
//     stepped from: a load below the round-off of a stiff part may still move it), or
//   - after a step, w <= 1, or w <= floor_slack (10) and the step did not halve ||g||
//     (the residual has stopped decreasing, within a small factor of its floor), or
//   - a full step of an exact factorization did not halve ||g|| and ||g|| <= sqrt(relative_
//     tolerance) * scale (quadratic convergence has stopped; scale is the larger of ||g_0||,
//     reference_residual and absolute_tolerance / relative_tolerance), or
//   - the line search fails with w <= floor_slack (no decrease is left to find),
// provided the answer has digits. When the floor is above sqrt(relative_tolerance) * scale,
// the residual no longer certifies the solution, so Newton estimates the iterate's error as
// the next Newton step, accuracy = ||S H^-1 g||_inf (state units: the residual's round-off
// propagated through the inverse stiffness, which is what a contrast of moduli amplifies), and
// compares it with solution_change = ||x - x_start||_inf, what the solve moved the state:
//   accuracy < 0.1 * solution_change (at least one reliable digit), or accuracy below
//   100 eps (1 + ||x||_inf) (as exact as positions are stored): round_off_floor;
//   otherwise ill_conditioned (not converged): the answer has no reliable digits.
// When the steps from a start within its floor have no digits and the diagonal ratio is below
// 1 / eps, the start is returned (round_off_floor at iteration 0: its residual was round-off,
// as a sliver element's at rest).
// A constant Hessian whose refinement steps stall with the residual above floor_slack times
// its floor (the factorization's solves have no digits left) is ill_conditioned too, as is a
// constant Hessian that fails to factorize. Each message gives the residual, the floor, and
// where estimated the accuracy and a condition estimate (the ratio of the Hessian's largest to
// smallest diagonal entry, a lower bound of its condition number).
//
// Constant Hessians: when every term declares hessian_is_constant() (linear elasticity,
// inertia, loads), the exact Hessian is factorized once per parameter vector p (and per
// revision of the terms' settings, EnergyTerm::hessian_revision) and that factor is kept
// across iterations, solve() calls (time steps) and the adjoint: an iteration then costs a
// gradient evaluation and a back-solve.
#include <chrono>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "forward/core/assembler.hpp"
#include "forward/solve/hessian_share.hpp"
#include "forward/solve/linear_solver.hpp"
#include "forward/solve/sparse_cholesky.hpp"

namespace tailor {

enum class NewtonHessian { adaptive, exact, projected };
std::string to_string(NewtonHessian hessian);

// Whether Newton's steps may come from CG preconditioned by a kept factorization
// (NewtonOptions::reuse_factorization).
enum class FactorReuse { automatic, on, off };
std::string to_string(FactorReuse reuse);

struct NewtonOptions {
  int max_iterations = 100;
  double relative_tolerance = 1e-9;
  double absolute_tolerance = 0.0;
  double step_tolerance = 1e-13;
  // When > 0, the relative tolerances refer to max(||g_0||, reference_residual) instead of
  // ||g_0||: a warm start next to the equilibrium has a tiny ||g_0|| that would make the
  // relative tolerance unreachable (pass, e.g., the residual at the undeformed state).
  double reference_residual = 0.0;
  // Which Hessian Newton factorizes:
  //  adaptive  (default) the exact Hessian whenever its Cholesky factorization succeeds
  //            (quadratic convergence near a stable equilibrium); when it is indefinite,
  //            the element-wise PSD-projected Hessian for that iteration and the next 1, 2,
  //            4, ... (up to 16) after consecutive failures, then exact is tried again.
  //  projected always projected: every step a descent direction, but only linear
  //            convergence where the exact Hessian differs (large rotations, compression).
  //  exact     always exact; an indefinite matrix is shifted until it is positive definite.
  NewtonHessian hessian = NewtonHessian::adaptive;
  // Inexact Newton with a kept factorization. The numeric factorization is kept across
  // iterations and solve() calls; an iteration that would factorize the exact Hessian first
  // solves H dy = -g by conjugate gradients preconditioned with the kept factor, when that factor
  // is an exact, positive definite (LL^T) Hessian of a nearby state or nearby parameters. CG
  // aims at the forcing tolerance min(0.1, ||g|| / scale) within reuse_max_cg_iterations; when
  // it ends above 0.1 or its step is not a descent direction, the iteration factorizes as
  // without reuse (and keeps that fresh factor); when it ends between the forcing tolerance and
  // 0.1, the step is taken and the next iteration factorizes. The convergence test is
  // unchanged, so the equilibrium is the same to the tolerance.
  //  automatic (default) CG with the kept factor where it pays and while it converges:
  //            - cost: the factorization's flop count (CHOLMOD's, from the symbolic analysis:
  //              the same on every run) is at least reuse_min_factor_over_solve back-solves
  //              (4 nnz(L) flops each) and reuse_min_factor_flops_per_slot times the number of
  //              Hessian slots assembled per iteration; below that a factorization is about as
  //              cheap as the extra assembly an inexact step may cost (small meshes);
  //            - convergence: within a solve(), CG is tried at the first iteration (a warm start
  //              next to the kept factor's state) and after full steps (line-search factor 1)
  //              that at least halved the residual; after a CG step that did not (a shortened
  //              step or a residual above half the last one), that solve factorizes every
  //              iteration, as without reuse.
  //            - parameters: the kept factor was factorized at the same parameters p (the
  //              iterations of one solve, time steps, load steps), unless
  //              reuse_across_parameters; a solve at new p (an optimizer's next design) first
  //              factorizes. Measured on per-element modulus recovery (docs/performance.md): CG
  //              with the previous design's factor made the forward solve cheaper but left the
  //              adjoint to factorize, slower per evaluation than factorizing once and
  //              back-solving.
  //  on        CG whenever the kept factor allows it (the rule above without its tests).
  //  off       every iteration that needs a new Hessian factorizes it.
  FactorReuse reuse_factorization = FactorReuse::automatic;
  bool reuse_across_parameters = false;
  double reuse_min_factor_over_solve = 30.0;
  // Measured with dynamics_bench (Neo-Hookean implicit steps, one thread, CPU time per step,
  // docs/performance.md): at 47 flops per slot (6k tets) CG and factorizing cost the same, at
  // 232 (20k tets) CG costs 17-20% less, at 502 (58k tets) 36-40% less.
  double reuse_min_factor_flops_per_slot = 100.0;
  // With a constant Hessian (see above), keep its factorization while p is unchanged. Off only
  // to measure what it saves.
  bool keep_constant_factorization = true;
  int reuse_max_cg_iterations = 20;
  double armijo = 1e-4;              // sufficient-decrease constant
  int max_line_search_steps = 40;    // halvings before the line search is declared stalled
  // An alternative linear solver for the steps (forward/solve/linear_solver.hpp; e.g. PETSc). Empty
  // (default): CHOLMOD with everything above. When set, every step solves the assembled Hessian
  // with it (setup + solve, to the solver's default tolerance), and the factor reuse options,
  // the diagonal shift and the adaptive switch to the projected Hessian do not apply.
  LinearSolverPtr linear_solver;
  std::ostream* progress = nullptr;  // one line per iteration when set
  // Optional hooks. direction_converged(x, dx): called with the full state and the full-space
  // Newton direction before each line search; true stops with status converged (a caller's
  // own test, e.g. IPC's bound on a time step's direction). after_step(x): called after each
  // accepted step with the new full state; it may change the terms' settings (a barrier
  // stiffness), the next iteration evaluates everything afresh.
  std::function<bool(const Vector& x, const Vector& dx)> direction_converged;
  std::function<void(const Vector& x)> after_step;
};

enum class NewtonStatus {
  converged,
  round_off_floor,  // converged as far as floating point allows (see the top of this file)
  ill_conditioned,  // the round-off floor is above the accuracy the tolerance asks for
  max_iterations,
  line_search_failed,
  non_finite,
  singular_matrix
};
std::string to_string(NewtonStatus status);

struct NewtonIteration {
  int iteration = 0;
  double energy = 0.0;
  double residual = 0.0;     // ||S^T dE/dx|| before the step
  double step_norm = 0.0;    // ||dx||_inf of the accepted step
  double step_length = 0.0;  // line-search factor alpha
  int line_search_steps = 0;
  bool used_ldlt = false;
  bool used_projected = false;         // the factorized Hessian was the PSD-projected one
  bool reused_factorization = false;   // the step came from CG preconditioned by a kept factor
  bool kept_constant_factor = false;   // the step solved with the kept factor of a constant Hessian
  int cg_iterations = 0;               // CG iterations tried (also when CG then fell back)
  double cg_relative_residual = 0.0;   // ||H dy + g|| / ||g|| where CG stopped
  int factorizations = 0;              // numeric factorizations in this iteration
  double assembly_seconds = 0.0;       // energy, gradient and Hessian assembly
  double factorization_seconds = 0.0;  // numeric factorization (analysis only once)
  double solve_seconds = 0.0;          // triangular solves (and CG iterations)
  double line_search_seconds = 0.0;    // energy evaluations of the line search
};

struct NewtonResult {
  NewtonStatus status = NewtonStatus::max_iterations;
  std::string message;
  int iterations = 0;
  double initial_residual = 0.0;
  double final_residual = 0.0;
  double final_energy = 0.0;
  double residual_floor = 0.0;      // ||f||_2 of the round-off floor estimate (0 when not estimated)
  double floor_ratio = 0.0;         // w = max_i |g_i| / f_i at the last iterate (0 when not estimated)
  // Where the floor decided (see the top of this file): the estimated error of the iterate,
  // ||S H^-1 g||_inf, and how far the solve moved the state, ||x - x_start||_inf (state units).
  double accuracy = 0.0;
  double solution_change = 0.0;
  double condition_estimate = 0.0;  // max / min |diagonal| of the exact Hessian (a lower bound)
  double analysis_seconds = 0.0;
  double total_seconds = 0.0;
  std::vector<NewtonIteration> history;
  int factorizations() const;     // numeric factorizations over all iterations
  int kept_factor_steps() const;  // steps by CG preconditioned with a kept factor
  int cg_iterations() const;      // CG iterations over all iterations (also of tries that fell back)
  bool converged() const {
    return status == NewtonStatus::converged || status == NewtonStatus::round_off_floor;
  }
  // A human-readable summary in the spirit of Ceres' FullReport().
  std::string report() const;
};

class NewtonSolver {
 public:
  explicit NewtonSolver(const Model& model, NewtonOptions options = {});

  // Solves from y (in: the initial guess, out: the last iterate). Never throws for numerical
  // failures: they are returned as a status with a message.
  NewtonResult solve(const Vector& p, Vector& y);

  NewtonOptions& options() { return options_; }
  ReducedAssembler& assembler() { return assembler_; }
  // The last reduced Hessian assembled (upper triangle). After a converged solve() it is the
  // Hessian at the returned iterate, in assembled_mode().
  const SparseMatrix& hessian() const { return hessian_; }
  HessianMode assembled_mode() const { return assembled_mode_; }
  // The last factorization. After a converged solve() it belongs to the previous iterate (the
  // last Newton step), not to hessian(): factorization_matches_hessian() is false then. With
  // reuse_factorization it may belong to an earlier iterate or an earlier solve() (another p).
  // factorization_is_exact(): it factors an exact, unshifted Hessian (possibly by LDL^T).
  SparseCholesky& factorization() { return cholesky_; }
  bool factorization_is_exact() const { return factor_is_exact_; }
  bool factorization_matches_hessian() const { return factor_matches_hessian_; }
  // Assemble and factorize the Hessian at y in the given mode (the adjoint uses exact).
  FactorizationResult factorize_hessian(const Vector& p, const Vector& y, HessianMode mode);
  // Distributed assembly (the linear solver assembles_by_parts(), decided at construction):
  // no process holds the whole Hessian (hessian() is empty, factorize_hessian() and the
  // assembler's Hessian are errors); each assembles its share (forward/solve/hessian_share.hpp).
  bool assembles_by_parts() const { return share_ != nullptr; }
  // Distributed assembly: sets the linear solver up with the exact Hessian at (p, y) (nothing
  // to do when its last set-up was that one, as after a converged solve()). False with a
  // message when the set-up fails.
  bool set_up_exact_share(const Vector& p, const Vector& y, std::string& message);

 private:
  // Adaptive Hessian choice across iterations (see NewtonHessian::adaptive).
  struct HessianChoice {
    int projected_left = 0;     // iterations still to run with the projected Hessian
    int projected_backoff = 1;  // ... and how many to run after the next failed exact attempt
  };
  HessianMode choose_mode(const HessianChoice& choice) const;
  // The kept factor is the exact constant Hessian's at these parameters (and term settings).
  bool constant_factor_matches(const Vector& p) const;
  void remember_constant_factor(const Vector& p);
  // The step from CG preconditioned by the kept factor (NewtonOptions::reuse_factorization);
  // false when CG did not give a usable descent step.
  bool kept_factor_step(const Vector& gradient, double residual, double scale, double target,
                        NewtonIteration& it, Vector& dy);
  // The step from a fresh factorization of the Hessian (switching to the projected Hessian or
  // shifting the diagonal until the direction is a descent direction). Returns an error
  // message when no descent direction was found.
  std::string factorized_step(const Vector& p, const Vector& y, const Vector& gradient, HessianMode& mode,
                              HessianChoice& choice, const LowRankHessian& low_rank, NewtonIteration& it,
                              Vector& dy);
  // The step from options_.linear_solver (empty string on success, else the error).
  std::string external_step(const Vector& p, const Vector& y, const Vector& gradient, NewtonIteration& it,
                            Vector& dy);
  // Backtracking line search on E from the largest admissible step; on success y is updated.
  // The first trial point's gradient is evaluated with its energy (the terms compute both in
  // one pass); when that point is accepted, its energy and gradient go to accepted_energy and
  // accepted_gradient (accepted_evaluated true), so the next iteration assembles only the
  // Hessian there.
  bool line_search(const Vector& p, Vector& y, const Vector& dy, double energy, const Vector& gradient,
                   double residual, NewtonIteration& it, double& accepted_energy, Vector& accepted_gradient,
                   bool& accepted_evaluated);
  // From the assembled (exact) Hessian: floor_rows_ = eps * sum_j |H_ij| per row, and the
  // ratio of its largest to smallest absolute diagonal entry (the condition estimate).
  double estimate_floor_rows();
  // Distributed assembly, from the norms the solver reports of its last set-up: every row
  // gets eps * ||H||_inf (a bound of each row's sum), and the condition estimate.
  double estimate_floor_rows(double h_norm, double max_diagonal, double min_diagonal);
  // w = max_i |g_i| / (floor_rows_i * (1 + ||x||_inf)), and ||floor_rows_||_2 (1 + ||x||_inf).
  std::pair<double, double> floor_ratio(const Vector& gradient, const Vector& x) const;
  // The estimated error of the iterate, ||S H^-1 g||_inf, with the kept factor when it is of an
  // exact Hessian (that of the last step), else the last step's direction.
  double error_estimate(const Vector& gradient, const NewtonIteration& last);
  // Distributed assembly: assembles this process's share at (p, y) in `mode`, and hands it to
  // the solver (set_up_share) when a step or an estimate needs it.
  void assemble_share(const Vector& p, const Vector& y, HessianMode mode);
  bool set_up_share(std::string& message);
  void apply_low_rank(const LowRankHessian& low_rank);
  // The kept factor can precondition CG on the exact Hessian: exact, unshifted, LL^T.
  bool can_precondition() const;
  // FactorReuse::automatic's cost test: a factorization costs enough flops against a back-solve
  // and against an iteration's assembly for CG with the kept factor to pay.
  bool reuse_pays() const;

  const Model& model_;
  NewtonOptions options_;
  ReducedAssembler assembler_;  // without a Hessian in distributed assembly
  SparseMatrix hessian_;
  // Distributed assembly: this process's share, where and how it was last assembled, and
  // whether the solver holds it.
  std::unique_ptr<HessianShare> share_;
  Vector share_p_, share_y_;
  HessianMode share_mode_ = HessianMode::exact;
  bool share_assembled_ = false, share_set_up_ = false;
  SparseCholesky cholesky_;
  HessianMode assembled_mode_ = HessianMode::projected;
  bool factor_is_exact_ = false;
  bool factor_matches_hessian_ = false;
  bool kept_factor_stale_ = false;  // reuse: the last CG missed its tolerance with the kept factor
  Vector factor_p_;                 // the parameters of the last factorization
  bool analyzed_ = false;
  // Key of the kept factor of a constant Hessian (valid while constant_factor_ is true).
  bool constant_factor_ = false;
  Vector constant_p_;
  std::vector<std::uint64_t> constant_revisions_;
  // factorized_step's report that a constant Hessian failed to factorize, and the condition
  // estimate it quotes.
  bool ill_conditioned_ = false;
  double condition_hint_ = 0.0;
  // eps * sum_j |H_ij| of the last exact Hessian solve() assembled (empty before one was, and
  // after factorize_hessian replaced it), and that Hessian's condition estimate.
  Vector floor_rows_;
  double floor_condition_ = 0.0;
};

}  // namespace tailor
