#pragma once
// The scene's choice of linear solver for the static Newton steps and the adjoint
// ("solver": {"linear_solver": "petsc", "petsc_options": "-ksp_type cg ..."}, docs/petsc.md).
//
// CHOLMOD needs nothing here (NewtonOptions::linear_solver stays empty). Every other back-end is
// made by a factory that the program registers: the problems library does not link PETSc, so
// bin/tailor built with TAILOR_HAVE_PETSC registers "petsc" at start-up, and a program that did
// not (or a build without PETSc) reports the scene key and the build option instead.
#include <string>

#include "forward/core/elimination.hpp"
#include "forward/solve/linear_solver.hpp"

namespace tailor {

struct LinearSolverChoice {
  std::string name;     // "petsc"
  std::string options;  // the back-end's options string ("petsc_options")
};

// Makes the solver; throws std::invalid_argument for options the back-end rejects.
using LinearSolverFactory = LinearSolverPtr (*)(const LinearSolverChoice&);

// Registers (or replaces) the factory of `name`. Not thread-safe: call it before the first scene.
void register_linear_solver(const std::string& name, LinearSolverFactory factory);
void unregister_linear_solver(const std::string& name);
bool linear_solver_registered(const std::string& name);
// The solver from the registered factory. Throws std::invalid_argument when none is registered
// for the name (the message says how to build one) or the back-end rejects the options.
LinearSolverPtr make_linear_solver(const LinearSolverChoice& choice);

// The positions (dim per vertex) of the free unknowns when they are whole vertices: every free
// unknown is one DOF (a Dirichlet selection), and the free unknowns dim*k .. dim*k + dim - 1 are
// the dim components of one vertex. Empty otherwise (e.g. a vertex fixed in one component only,
// or a constraint that combines DOFs). `positions` holds dim values per vertex.
Vector free_vertex_coordinates(const Elimination& elimination, int dim, const Vector& positions);
// solver.set_vertex_coordinates with them when the free unknowns are whole vertices.
void give_vertex_coordinates(LinearSolver& solver, const Elimination& elimination, int dim,
                             const Vector& positions);

}  // namespace tailor
