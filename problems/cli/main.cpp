// bin/tailor: the command line is a library function (problems/cli/run_cli.hpp). Built with the
// PETSc back-end, it first starts PETSc and MPI and registers the "petsc" linear solver
// (problems/cli/petsc_command_line.hpp, docs/petsc.md). First of all it makes sure OpenBLAS runs
// the kernels this CPU supports, executing itself again if it must (docs/performance.md).
#include "forward/solve/blas_info.hpp"
#include "problems/cli/run_cli.hpp"
#ifdef TAILOR_HAVE_STUDIO
#include "problems/studio/studio_verb.hpp"
#endif
#ifdef TAILOR_HAVE_PETSC
#include "problems/cli/petsc_command_line.hpp"
#endif

int main(int argc, char** argv) {
  tailor::use_cpu_blas_core(argv);  // OpenBLAS's kernels for this CPU (forward/solve/blas_info.hpp)
#ifdef TAILOR_HAVE_STUDIO
  tailor::register_verb(tailor::studio::studio_verb());  // docs/studio.md
#endif
#ifdef TAILOR_HAVE_PETSC
  return tailor::run_cli_with_petsc(argc, argv);
#else
  return tailor::run_cli(argc, argv);
#endif
}
