#include "problems/cli/petsc_command_line.hpp"

#include <cctype>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <ostream>
#include <stdexcept>

#include "optimizers/backend_registry.hpp"
#include "petsc/petsc_linear_solver.hpp"
#include "problems/cli/run_cli.hpp"
#include "problems/fem/linear_solver_choice.hpp"
#include "problems/output_process.hpp"

namespace tailor {
namespace {

bool is_petsc_option(const std::string& word) {
  return word.size() > 2 && word[0] == '-' && std::isalpha(static_cast<unsigned char>(word[1]));
}

bool is_option_value(const std::string& word) {
  return word.empty() || word[0] != '-' ||
         (word.size() > 1 && (std::isdigit(static_cast<unsigned char>(word[1])) || word[1] == '.'));
}

// PETSc (and MPI) for this process: started at once under mpiexec or with PETSc options on the
// command line, else by the first "petsc" scene, so that a run that never uses it (most, and
// the command-line tests) does not pay for MPI's singleton start-up.
struct LazySession {
  int* argc = nullptr;
  char*** argv = nullptr;
  std::unique_ptr<PetscSession> session;
  void start() {
    if (!session) session = std::make_unique<PetscSession>(argc, argv);
  }
};

LazySession& lazy_session() {
  static LazySession lazy;
  return lazy;
}

LinearSolverPtr make_petsc_solver(const LinearSolverChoice& choice) {
  lazy_session().start();
  PetscSolverOptions options;
  options.options = choice.options;
  return std::make_shared<PetscLinearSolver>(options);
}

// Whether an MPI launcher started this process (OpenMPI, MPICH/Hydra, PMIx and Slurm set these).
bool launched_by_mpiexec() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "SLURM_PROCID"})
    if (std::getenv(name)) return true;
  return false;
}

}  // namespace

namespace {

// argv split into tailor's words (petsc = false) or PETSc's (true), argv[0] in both.
std::vector<std::string> split_command_line(int argc, const char* const* argv, bool petsc) {
  std::vector<std::string> kept;
  if (argc > 0) kept.emplace_back(argv[0]);
  for (int i = 1; i < argc; ++i) {
    if (!is_petsc_option(argv[i])) {
      if (!petsc) kept.emplace_back(argv[i]);
      continue;
    }
    if (petsc) kept.emplace_back(argv[i]);
    if (i + 1 < argc && is_option_value(argv[i + 1])) {
      ++i;
      if (petsc) kept.emplace_back(argv[i]);
    }
  }
  return kept;
}

}  // namespace

std::vector<std::string> without_petsc_options(int argc, const char* const* argv) {
  return split_command_line(argc, argv, false);
}

std::vector<std::string> petsc_options_only(int argc, const char* const* argv) {
  return split_command_line(argc, argv, true);
}

int run_cli_with_petsc(int argc, char** argv) {
  const std::vector<std::string> words = without_petsc_options(argc, argv);
  // PETSc sees only its own options (its database then holds nothing of tailor's flags).
  std::vector<std::string> petsc_words = petsc_options_only(argc, argv);
  std::vector<char*> petsc_pointers;
  for (std::string& word : petsc_words) petsc_pointers.push_back(word.data());
  petsc_pointers.push_back(nullptr);
  int petsc_argc = static_cast<int>(petsc_words.size());
  char** petsc_argv = petsc_pointers.data();
  LazySession& lazy = lazy_session();
  lazy.argc = &petsc_argc;
  lazy.argv = &petsc_argv;
  try {
    if (launched_by_mpiexec() || petsc_argc > 1) lazy.start();
  } catch (const std::exception& e) {
    std::cerr << "tailor: error: " << e.what() << "\n";
    return 1;
  }
  const bool root = !lazy.session || PetscSession::rank() == 0;
  set_writes_output(root);
  register_linear_solver("petsc", make_petsc_solver);
  // Ipopt's MUMPS resolves to PETSc's MPI build in this program: MPI must be running first.
  set_ipopt_prelude([] { lazy_session().start(); });
  std::vector<const char*> tailor_argv;
  for (const std::string& word : words) tailor_argv.push_back(word.c_str());
  // The other ranks compute the same and say nothing (a stream without a buffer drops output).
  std::ostream silent(nullptr);
  const int code = run_cli(static_cast<int>(tailor_argv.size()), tailor_argv.data(),
                           root ? std::cout : silent, root ? std::cerr : silent);
  lazy.session.reset();  // after the scene's solvers are gone
  return code;
}

}  // namespace tailor
