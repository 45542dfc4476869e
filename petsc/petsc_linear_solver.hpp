#pragma once
// PetscLinearSolver: the reduced Hessian solved by PETSc's KSP across the ranks of
// MPI_COMM_WORLD (docs/petsc.md).
//
// Replicated assembly, distributed solve: every rank runs the whole program on the whole model
// (assembly, Newton, the adjoint's right-hand sides); only the linear solves are distributed.
// setup() takes the full upper triangle on every rank, and each rank copies its contiguous
// block of rows (PETSc's default split of n rows) into a MATMPIAIJ matrix; solve() takes the
// full right-hand side on every rank and returns the full solution on every rank.
// Assembly by parts (assemble_by_parts, -tailor_assemble_by_parts): each rank assembles only
// its own elements' part of the Hessian and setup_share() sums the parts in PETSc.
//
// Defaults: CG with algebraic multigrid (GAMG) to a relative residual of 1e-10 when the caller
// passes no tolerance. PETSc's options database overrides them (KSPSetFromOptions): the
// command line given to PetscInitialize and the `options` string (e.g. "-ksp_type preonly
// -pc_type cholesky -pc_factor_mat_solver_type mumps") are both honoured; an unknown or invalid
// option value is an error (std::invalid_argument from the constructor, naming the option),
// and so is an option of the string that the solver never read (std::invalid_argument from the
// first solve(), e.g. a misspelt name). The string's options go into PETSc's global database
// while the solver lives (they replace the command line's values of the same names) and are
// removed when it is destroyed.
#include <memory>
#include <string>

#include "forward/solve/linear_solver.hpp"

namespace tailor {

// PetscInitialize / PetscFinalize for the process (once; nothing when PETSc is already
// initialized by someone else). Construct it before the first PetscLinearSolver.
class PetscSession {
 public:
  PetscSession(int* argc, char*** argv);
  ~PetscSession();
  PetscSession(const PetscSession&) = delete;
  PetscSession& operator=(const PetscSession&) = delete;
  static int rank();
  static int size();

 private:
  bool owns_ = false;
};

struct PetscSolverOptions {
  std::string options;              // PETSc options, e.g. "-ksp_type cg -pc_type gamg"
  double relative_tolerance = 1e-10;  // when solve() is given none
  int max_iterations = 10000;
  // Distributed assembly (docs/petsc.md): each rank assembles the Hessian of the elements it
  // owns and the matrix is their sum (setup_share), instead of every rank assembling all of it.
  // Also on with the PETSc option -tailor_assemble_by_parts (command line or `options`).
  bool assemble_by_parts = false;
};

class PetscLinearSolver final : public LinearSolver {
 public:
  explicit PetscLinearSolver(PetscSolverOptions options = {});
  ~PetscLinearSolver() override;
  std::string name() const override { return "petsc"; }
  bool setup(const SparseMatrix& upper, std::string& message) override;
  LinearSolveStats solve(const Vector& b, double relative_tolerance, Vector& x) override;
  bool is_root() const override;
  LinearSolverInfo info() const override;
  // With coordinates, the rows are split across the ranks by whole vertices, the matrix has
  // block size dim, and the rigid-body modes (MatNullSpaceCreateRigidBody: 3 in 2D, 6 in 3D) are
  // its near-null space, which GAMG uses to build its coarse spaces (ignored by other PCs).
  void set_vertex_coordinates(int dim, const Vector& coordinates) override;
  bool assembles_by_parts() const override;
  // Whether this rank owns row `unknown` of an n-unknown matrix: the split of setup().
  bool owns_unknown(int unknown, int num_unknowns) const override;
  // The matrix is the sum over the ranks of their `upper_share` (each the upper triangle of
  // its elements' part, n x n): PETSc's COO assembly adds them, across ranks too. No rank holds
  // the whole matrix, so solve() measures its residual with PETSc's product.
  bool setup_share(const SparseMatrix& upper_share, std::string& message) override;
  bool matrix_norms(double& inf_norm, double& max_abs_diagonal, double& min_abs_diagonal) const override;
  // y = A x with the last set-up's matrix (every rank gets all of y); for tests.
  Vector multiply(const Vector& x) const;
  // What KSPSetFromOptions chose: "cg/gamg", "preonly/cholesky", ...
  std::string method() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  PetscSolverOptions options_;
};

}  // namespace tailor
