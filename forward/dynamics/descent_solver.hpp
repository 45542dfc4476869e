#pragma once
// Preconditioned gradient descent with Chebyshev acceleration for one minimisation
//   y* = argmin_y E(x0 + S y, p)
// (Wang & Yang 2016, "Descent methods for elastic body simulation on the GPU"; docs/dynamics.md,
// "The descent solver"), the parallel alternative to NewtonSolver for the incremental potentials
// of implicit time steps (forward/dynamics/descent_time_stepper.hpp). Each iteration is one
// evaluation pass (BlockJacobiPass: energy, reduced gradient g and the block-Jacobi inverse
// D^-1 at the trial point) and vector updates:
//   u~ = u_k - alpha D^-1 g_k,
//   u_{k+1} = omega_{k+1} (u~ - u_{k-1}) + u_{k-1},
//   omega_1 = 1, omega_2 = 2 / (2 - rho^2), omega_{k+1} = 4 / (4 - rho^2 omega_k).
// Simplified Wolfe rule: a trial point whose energy is above the current one's (or is not
// finite) is rejected: alpha is halved and the acceleration restarts (omega = 1, u_{k-1} = u_k).
// So the accepted iterates never raise E, up to E's round-off (DescentEvaluation::
// energy_roundoff): within it, where comparing energies says nothing, a trial point is accepted
// when its residual is smaller.
//
// rho, the spectral radius of the plain iteration u -> u - alpha D^-1 g, is estimated once per
// solver (kept across solves, e.g. the steps of one scene) unless given: the first
// rho_estimation_iterations accepted iterations run without acceleration at a fixed alpha, and
//   rho = (||g_N|| / ||g_{N/2}||)^(1 / (N - N/2)),
// the mean contraction of the residual over the second half of that window (the power method
// on the iteration matrix: the residual's ratio tends to the dominant eigenvalue's modulus;
// the first half lets the other components decay). A rejection restarts the window at the
// halved alpha, and the alpha of the estimate becomes the solver's starting step length. The
// estimate is clamped to [0, rho_max].
//
// Stopping: Newton's measure (forward/solve/newton.hpp), ||g_k|| <= relative_tolerance *
// max(||g_0||, reference_residual) or ||g_k|| <= absolute_tolerance; else after max_iterations
// passes (status iteration_budget: the step is usable, the reached residual is reported), or
// when alpha has been halved below min_step_length times its start without a decrease
// (status stalled: the energy's round-off hides further decrease).
//
// Where it runs (DescentOptions::device; docs/dynamics.md, "The GPU path"): the loop above runs on
// the host; the passes and vector updates run in a DescentBackend (descent_backend.hpp): on the
// CPU with either preconditioner rule, or on a CUDA device with the vertex-block rule.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "forward/dynamics/descent_backend.hpp"
#include "forward/dynamics/descent_block_jacobi.hpp"

namespace tailor {

// The block-Jacobi preconditioner's rule. projected_hessian: diagonal blocks of the Hessian with
// every term's element tangent projected to PSD as Newton's projected mode does (any model
// BlockJacobiPass takes). vertex_blocks: each tet's exact diagonal 3 x 3 blocks projected to PSD
// one by one, plus the constant terms' blocks (descent_vertex_blocks.hpp: tet Neo-Hookean/StVK
// and constant-Hessian terms only); the rule the device runs, so the CPU can reproduce it.
enum class DescentPreconditioner { projected_hessian, vertex_blocks };
// cpu: the host, with `preconditioner`. gpu: a CUDA device with the vertex-block rule (an error
// when the build has no CUDA, no device is present or the rule does not cover the model).
// automatic: the device when all of that holds, else the CPU with `preconditioner`.
enum class DescentDevice { cpu, gpu, automatic };
std::string to_string(DescentDevice device);

struct DescentOptions {
  int max_iterations = 500;          // evaluation passes per solve after the first
  double relative_tolerance = 1e-6;  // Newton's relative residual measure
  double absolute_tolerance = 0.0;   // [force]
  double reference_residual = 0.0;   // scale = max(||g_0||, this) (set per step by the stepper)
  // alpha at the first solve; 0 = automatic: step_length_factor / lambda_max(D^-1 H), the
  // largest eigenvalue by power_iterations steps of the power method with the exact Hessian at
  // the first solve's start (plain descent is stable for alpha lambda_max < 2; the power method
  // approaches lambda_max from below, so the factor keeps a margin).
  double step_length = 0.0;
  double step_length_factor = 1.5;
  int power_iterations = 20;
  std::optional<double> rho;         // spectral radius; empty = estimated (see above); 0 = no acceleration
  int rho_estimation_iterations = 16;
  double rho_max = 0.9999;
  double min_step_length = 1e-10;    // relative to the solve's starting alpha
  bool energy_check = true;          // the simplified Wolfe rule; false only to show what it prevents
  int block_size = 3;                // DOFs per vertex: the preconditioner's blocks
  bool keep_history = false;         // record every iteration in DescentResult::history
  DescentPreconditioner preconditioner = DescentPreconditioner::projected_hessian;
  DescentDevice device = DescentDevice::cpu;
};

enum class DescentStatus { converged, iteration_budget, stalled, non_finite };
std::string to_string(DescentStatus status);

struct DescentIteration {
  double energy = 0.0;    // E at the trial point
  double residual = 0.0;  // ||g|| at the trial point
  double step_length = 0.0;
  double omega = 1.0;
  bool accepted = false;
};

struct DescentResult {
  DescentStatus status = DescentStatus::iteration_budget;
  std::string message;
  int iterations = 0;  // passes after the first evaluation
  int rejections = 0;  // trial points the energy check rejected
  double initial_residual = 0.0, final_residual = 0.0, scale = 0.0;
  double initial_energy = 0.0, final_energy = 0.0;
  double rho = 0.0;  // the spectral radius used at the end (0 while still estimating)
  double seconds = 0.0;
  std::vector<DescentIteration> history;  // with keep_history
  // A usable answer: converged, or stopped by the budget or round-off with a finite state.
  bool usable() const { return status != DescentStatus::non_finite; }
  bool converged() const { return status == DescentStatus::converged; }
};

class DescentSolver {
 public:
  // Throws std::invalid_argument for bad options or a model the chosen rule does not cover,
  // std::runtime_error for device "gpu" without a usable CUDA device.
  DescentSolver(const Model& model, DescentOptions options);

  // Minimises from y (in: the warm start, out: the last accepted iterate).
  DescentResult solve(const Vector& p, Vector& y);

  DescentOptions& options() { return options_; }
  // The CPU pass of the projected_hessian rule; throws std::logic_error for the other backends.
  BlockJacobiPass& pass();
  // "cpu" or "gpu": where the passes run.
  std::string device() const { return backend_->device(); }
  // The spectral radius in use (the option, or the estimate; empty while estimating).
  std::optional<double> spectral_radius() const;
  // The step length alpha each solve starts with (that of the rho estimate once there is one).
  double step_length() const { return start_alpha_.value_or(0.0); }

 private:
  DescentOptions options_;
  std::unique_ptr<DescentBackend> backend_;
  std::optional<double> estimated_rho_;
  std::optional<double> start_alpha_;
};

}  // namespace tailor
