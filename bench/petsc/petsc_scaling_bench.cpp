// PETSc back-end against CHOLMOD on the reduced Hessian of a clamped linear-elastic cantilever
// (bench/cantilever.hpp) for a few mesh sizes: seconds of a set-up (CHOLMOD: numeric
// factorization after a symbolic analysis; PETSc: matrix copy + KSPSetUp, e.g. GAMG's
// hierarchy) and of one solve to a relative residual of 1e-10, medians of 3, and each rank's
// peak resident memory. Run under mpiexec with 1 and 2 ranks (docs/petsc.md):
//   mpiexec -n 2 build/bin/petsc_scaling_bench [report.json] [PETSc options]
// Every rank holds the whole model and matrix (replicated assembly); CHOLMOD runs on rank 0's
// copy only for the comparison (in a real run every rank would hold the model, not a factor).
#include <mpi.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "bench/bench_cli.hpp"
#include "bench/cantilever.hpp"
#include "forward/core/assembler.hpp"
#include "forward/solve/sparse_cholesky.hpp"
#include "petsc/petsc_linear_solver.hpp"

namespace {

using namespace tailor;
using namespace tailor::bench;

// This process's peak resident memory (VmHWM) in MiB.
double peak_mib() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0.0;
}

}  // namespace

int main(int argc, char** argv) {
  PetscSession session(&argc, &argv);  // reads PETSc's own flags
  const std::string out = argc > 1 ? argv[1] : "petsc_scaling_bench.json";
  const int rank = PetscSession::rank(), ranks = PetscSession::size();
  Json json = report("petsc_scaling_bench");
  json["ranks"] = ranks;
  json["relative_tolerance"] = 1e-10;
  Json rows = Json::array();
  if (rank == 0)
    std::printf("%5s %8s %8s | %9s %9s %8s | %9s %9s %6s %8s %s\n", "ranks", "tets", "unknowns", "chol fact",
                "chol solve", "chol MiB", "petsc setup", "petsc solve", "its", "MiB/rank", "method");
  for (int target : {6000, 24000, 96000}) {
    Cantilever c = make_cantilever(4.0, cantilever_cells(target, 4.0), MaterialKind::linear);
    const Vector p = cantilever_parameters(c, 1000.0, 0.3);
    ReducedAssembler assembler(*c.model);
    SparseMatrix h;
    const Vector y = c.model->elimination().restrict_state(c.rest);
    assembler.evaluate(y, p, nullptr, nullptr, &h, HessianMode::exact);
    const Vector b = Vector::Ones(h.rows());
    std::vector<double> chol_fact, chol_solve, petsc_setup, petsc_solve;
    double chol_mib = 0.0;
    if (rank == 0) {
      SparseCholesky cholesky;
      cholesky.analyze(h);
      for (int r = 0; r < 3; ++r) {
        auto t0 = Clock::now();
        cholesky.factorize(h);
        chol_fact.push_back(seconds_since(t0));
        t0 = Clock::now();
        const Vector x = cholesky.solve(b);
        chol_solve.push_back(seconds_since(t0));
      }
      chol_mib = peak_mib();
    }
    MPI_Barrier(MPI_COMM_WORLD);
    PetscLinearSolver solver;
    LinearSolveStats stats;
    for (int r = 0; r < 3; ++r) {
      std::string message;
      MPI_Barrier(MPI_COMM_WORLD);
      auto t0 = Clock::now();
      if (!solver.setup(h, message)) {
        std::fprintf(stderr, "setup failed: %s\n", message.c_str());
        return 1;
      }
      petsc_setup.push_back(seconds_since(t0));
      Vector x;
      MPI_Barrier(MPI_COMM_WORLD);
      t0 = Clock::now();
      stats = solver.solve(b, 1e-10, x);
      petsc_solve.push_back(seconds_since(t0));
    }
    double mib = peak_mib();
    std::vector<double> per_rank(ranks);
    MPI_Gather(&mib, 1, MPI_DOUBLE, per_rank.data(), 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    if (rank != 0) continue;
    Json row;
    row["tets"] = c.mesh.num_elements();
    row["unknowns"] = h.rows();
    row["cholmod_factorize_seconds"] = median(chol_fact);
    row["cholmod_solve_seconds"] = median(chol_solve);
    row["cholmod_peak_mib"] = chol_mib;
    row["petsc_setup_seconds"] = median(petsc_setup);
    row["petsc_solve_seconds"] = median(petsc_solve);
    row["petsc_iterations"] = stats.iterations;
    row["petsc_relative_residual"] = stats.relative_residual;
    row["petsc_method"] = solver.method();
    row["peak_mib_per_rank"] = array(per_rank);
    row["petsc_over_cholmod_total"] =
        (median(petsc_setup) + median(petsc_solve)) / (median(chol_fact) + median(chol_solve));
    rows.push_back(row);
    double max_mib = 0.0;
    for (double v : per_rank) max_mib = std::max(max_mib, v);
    std::printf("%5d %8d %8d | %9.4f %9.4f %8.0f | %11.4f %11.4f %6d %8.0f %s\n", ranks, c.mesh.num_elements(),
                static_cast<int>(h.rows()), median(chol_fact), median(chol_solve), chol_mib, median(petsc_setup),
                median(petsc_solve), stats.iterations, max_mib, solver.method().c_str());
  }
  if (rank == 0) {
    json["rows"] = rows;
    if (!write_report(out, json, "petsc_scaling_bench")) return 1;
  }
  return 0;
}
