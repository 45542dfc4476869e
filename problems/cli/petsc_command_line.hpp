#pragma once
// bin/tailor with the PETSc back-end (docs/petsc.md, "Scenes and the command line").
//
// Every rank runs the whole command (the replicated design of petsc_linear_solver.hpp); only
// the linear solves of "linear_solver": "petsc" scenes are distributed. PETSc reads its own
// options (-ksp_type cg, -ksp_monitor, ...) from the command line, and tailor's parser gets the
// rest; rank 0 alone prints and writes files.
#include <string>
#include <vector>

namespace tailor {

// The command line without PETSc's options, for tailor's parser. A PETSc option is a word with
// one dash and more than one letter ("-ksp_type"); as PETSc reads it, the next word is its value
// unless that starts with a dash (a negative number is a value).
std::vector<std::string> without_petsc_options(int argc, const char* const* argv);
// The other words: argv[0] and PETSc's options with their values, for PetscInitialize.
std::vector<std::string> petsc_options_only(int argc, const char* const* argv);

// "petsc" registered as a linear solver (problems/fem/linear_solver_choice.hpp), output on rank 0
// only, then tailor::run_cli. PETSc (PetscSession, with the whole command line) starts at once
// under an MPI launcher or when the command line has PETSc options, else when a scene first asks
// for "petsc"; a run without it never starts MPI.
int run_cli_with_petsc(int argc, char** argv);

}  // namespace tailor
