#pragma once
// A LinearSolver (linear_solver.hpp) for Newton's steps: conjugate gradients on the exact Hessian
// H, preconditioned by the Cholesky factor of a fixed symmetric positive definite matrix P given
// once, of the same size and unknown order as H. P is factorized at construction and never again:
// each Newton iteration costs H's assembly, then per CG iteration one product with H and one
// back-solve with P's factor, and no factorization of H.
//
// Meant for a P that is spectrally close to H and cheaper to factor: the P1-tet Hessian on the
// node lattice of a meshless (MLS) discretization, which couples one lattice layer where the MLS
// Hessian couples two (docs/meshless.md, "Bench"), or H's own factor at the rest state. The CG
// iteration count is then bounded independently of the mesh size as long as the two operators
// are equivalent (both discretize the same elasticity), and grows as H drifts from P (large
// strains). Solves aim at ||b - H x|| <= tolerance ||b|| (default 1e-8, tight enough that Newton
// takes the same iterations as with a direct solve).
#include <memory>

#include "forward/solve/linear_solver.hpp"
#include "forward/solve/sparse_cholesky.hpp"

namespace tailor {

struct FixedPreconditionerOptions {
  double relative_tolerance = 1e-8;  // the default of solve() given none
  int max_iterations = 500;
};

class FixedPreconditionerCg : public LinearSolver {
 public:
  // preconditioner_upper: upper triangle of P (compressed columns). std::runtime_error when P
  // does not factorize as LL^T (not positive definite).
  explicit FixedPreconditionerCg(const SparseMatrix& preconditioner_upper, FixedPreconditionerOptions options = {});

  std::string name() const override { return "fixed-preconditioner CG"; }
  bool setup(const SparseMatrix& upper, std::string& message) override;
  LinearSolveStats solve(const Vector& b, double relative_tolerance, Vector& x) override;
  LinearSolverInfo info() const override;

  const SparseCholesky& preconditioner() const { return factor_; }

 private:
  FixedPreconditionerOptions options_;
  SparseCholesky factor_;
  SparseMatrix hessian_;
  int solves_ = 0;
  long long iterations_ = 0;
  std::vector<int> recent_;
  LinearSolveStats last_;
};

}  // namespace tailor
