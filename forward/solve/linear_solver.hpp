#pragma once
// LinearSolver: an alternative back-end for the solves with the reduced Hessian H (symmetric,
// given as the upper triangle of a compressed column matrix, as ReducedAssembler assembles it).
//
// The default path (NewtonOptions::linear_solver empty) is CHOLMOD's SparseCholesky with all of
// NewtonSolver's factor reuse; nothing of it changes when no LinearSolver is set. A LinearSolver
// set on NewtonOptions takes over Newton's steps (setup() of the exact Hessian, one solve() per
// step; no projected Hessian, no diagonal shift, no kept factor, no low-rank update) and
// StaticFunctional's adjoint solves. It is meant for positive definite Hessians (static linear
// and stable nonlinear equilibria); setup() or solve() report failure instead of shifting.
#include <memory>
#include <string>
#include <vector>

#include "forward/core/types.hpp"

namespace tailor {

struct LinearSolveStats {
  bool converged = false;
  int iterations = 0;               // of an iterative solver (0 for a direct one)
  double relative_residual = 0.0;   // ||b - A x|| / ||b|| as the solver reports it
  double relative_tolerance = 0.0;  // the tolerance the solve aimed at
  std::string message;              // why not, when !converged
};

// What a run's report records about the solver: its settings in effect and its solves so far.
// A direct solver leaves the iterative fields empty.
struct LinearSolverInfo {
  std::string name;                   // "petsc"
  std::string options;                // the options the solver was given (e.g. a PETSc options string)
  std::string options_in_effect;      // every option the solver's library read from, when it has a database
  std::string krylov_method;          // e.g. PETSc's KSP type "cg"
  std::string preconditioner;         // e.g. PETSc's PC type "gamg"
  std::string factorization_package;  // of a factorization preconditioner ("mumps"), else empty
  double relative_tolerance = 0.0;    // the default for solves given none (the adjoint sets its own)
  double absolute_tolerance = 0.0;
  double divergence_tolerance = 0.0;
  int max_iterations = 0;
  int processes = 1;                  // MPI ranks taking part in each solve
  bool assembles_by_parts = false;    // distributed assembly (LinearSolver::assembles_by_parts)
  bool near_null_space = false;       // rigid-body modes given to the preconditioner
  int solves = 0;                     // since construction
  long long iterations = 0;           // summed over those solves
  std::vector<int> recent_iterations; // of the last solves, oldest first (a few)
  LinearSolveStats last;              // the last solve
};

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  virtual std::string name() const = 0;
  // New matrix values (the pattern may change too). Returns false with a message on failure.
  virtual bool setup(const SparseMatrix& upper, std::string& message) = 0;
  // Solves A x = b with the last setup to the relative residual `relative_tolerance`
  // (<= 0: the solver's own default, see its documentation). x is complete on every caller.
  virtual LinearSolveStats solve(const Vector& b, double relative_tolerance, Vector& x) = 0;
  // Whether this process writes reports and files (rank 0 of a distributed solver).
  virtual bool is_root() const { return true; }
  // The settings in effect and the solves so far, for reports.
  virtual LinearSolverInfo info() const {
    LinearSolverInfo i;
    i.name = name();
    return i;
  }
  // The unknowns are `dim` components of the vertices at `coordinates` (dim values per vertex,
  // in the order of the unknowns): a solver may build the rigid-body modes from them (the
  // near-null space of elasticity, for algebraic multigrid). Called before setup(); the default
  // ignores it.
  virtual void set_vertex_coordinates(int /*dim*/, const Vector& /*coordinates*/) {}

  // Distributed assembly (a solver over several processes that each assemble a share of H).
  // When assembles_by_parts() is true, NewtonSolver does not assemble H on each process:
  // every element goes to the process that owns one of its free unknowns (owns_unknown, the
  // same split as the solver's rows), each process assembles the upper triangle of its elements'
  // part of H (in the numbering of all n unknowns) and hands it to setup_share(); H is the sum of
  // the processes' parts. Energy, gradient and the line search stay replicated. The defaults
  // (one process holding everything) keep setup().
  virtual bool assembles_by_parts() const { return false; }
  virtual bool owns_unknown(int /*unknown*/, int /*num_unknowns*/) const { return true; }
  virtual bool setup_share(const SparseMatrix& upper_share, std::string& message) {
    return setup(upper_share, message);
  }
  // ||H||_inf and the largest and smallest |H_ii| of the last setup (for Newton's round-off
  // floor when no process holds H); false when the solver cannot tell.
  virtual bool matrix_norms(double& /*inf_norm*/, double& /*max_abs_diagonal*/,
                            double& /*min_abs_diagonal*/) const {
    return false;
  }
};
using LinearSolverPtr = std::shared_ptr<LinearSolver>;

}  // namespace tailor
