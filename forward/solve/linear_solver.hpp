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

#include "forward/core/types.hpp"

namespace tailor {

struct LinearSolveStats {
  bool converged = false;
  int iterations = 0;               // of an iterative solver (0 for a direct one)
  double relative_residual = 0.0;   // ||b - A x|| / ||b|| as the solver reports it
  double relative_tolerance = 0.0;  // the tolerance the solve aimed at
  std::string message;              // why not, when !converged
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
};
using LinearSolverPtr = std::shared_ptr<LinearSolver>;

}  // namespace tailor
