// Memory and time per rank of one linear solve with the reduced Hessian of a clamped
// linear-elastic cantilever (bench/cantilever.hpp, E = 1000, nu = 0.3), in one of three modes
// (docs/petsc.md, "Figures"):
//   --mode cholmod      one process: assembly (ReducedAssembler) + CHOLMOD (analysis,
//                       factorization, solve): tailor's default path;
//   --mode replicated   every rank assembles the whole Hessian and copies its rows into PETSc
//                       (PetscLinearSolver::setup);
//   --mode by-parts     every rank assembles the Hessian of the elements it owns
//                       (forward/solve/hessian_share.hpp) and PETSc sums the shares
//                       (PetscLinearSolver::setup_share): distributed assembly.
// Per mesh size: assembly, set-up (CHOLMOD: factorization; PETSc: matrix + KSPSetUp, e.g. GAMG's
// hierarchy) and solve seconds (to a relative residual of 1e-10, medians of --repeats), CG
// iterations, and each rank's resident memory while it holds everything of that size (VmRSS)
// and its peak so far (VmHWM; sizes run in increasing order, so it is that size's peak). The
// rigid-body modes are the near-null space (the clamped unknowns are whole vertices) unless
// --no-near-null-space. PETSc options (-ksp_type ..., -log_view) may follow on the command line.
//
//   mpiexec -n 2 build/bin/petsc_scaling_bench --mode by-parts --tets 24000,96000,384000
#include <mpi.h>

#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bench/bench_cli.hpp"
#include "bench/cantilever.hpp"
#include "forward/core/assembler.hpp"
#include "forward/solve/hessian_share.hpp"
#include "forward/solve/sparse_cholesky.hpp"
#include "petsc/petsc_linear_solver.hpp"
#include "problems/cli/petsc_command_line.hpp"

namespace {

using namespace tailor;
using namespace tailor::bench;

// This process's resident memory now (VmRSS) or at its peak so far (VmHWM), in MiB.
double status_mib(const char* key) {
  std::ifstream status("/proc/self/status");
  const std::string prefix = std::string(key) + ":";
  for (std::string line; std::getline(status, line);)
    if (line.rfind(prefix, 0) == 0) return std::stod(line.substr(prefix.size())) / 1024.0;
  return 0.0;
}

std::vector<double> gather(double value) {
  std::vector<double> all(static_cast<std::size_t>(PetscSession::size()));
  MPI_Gather(&value, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  return all;
}

double max_of(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, x);
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  PetscSession session(&argc, &argv);  // reads PETSc's own flags
  const std::vector<std::string> words = without_petsc_options(argc, argv);
  std::vector<const char*> ours;
  for (const std::string& w : words) ours.push_back(w.c_str());

  std::vector<int> tets{6000, 24000, 96000};
  int repeats = 3;
  bool no_modes = false;
  std::string mode = "by-parts", out = "petsc_scaling_bench.json";
  Cli cli("petsc_scaling_bench",
          "memory and time per rank of a solve: CHOLMOD, PETSc replicated, PETSc by parts");
  cli.tets(tets);
  cli.repeats(repeats);
  cli.choice("--mode", mode, "cholmod, replicated or by-parts", {"cholmod", "replicated", "by-parts"});
  cli.flag("--no-near-null-space", no_modes, "GAMG without the rigid-body modes");
  cli.out(out);
  if (const auto exit = cli.parse(static_cast<int>(ours.size()), ours.data())) return *exit;
  const int rank = PetscSession::rank(), ranks = PetscSession::size();
  if (mode == "cholmod" && ranks != 1) return cli.usage_error("--mode cholmod runs on one process");

  Json json = report("petsc_scaling_bench");
  json["mode"] = mode;
  json["ranks"] = ranks;
  json["relative_tolerance"] = 1e-10;
  json["near_null_space"] = !no_modes && mode != "cholmod";
  Json rows = Json::array();
  if (rank == 0)
    std::printf("%-10s %5s %8s %8s | %9s %9s %9s %5s | %11s %11s  %s\n", "mode", "ranks", "tets", "unknowns",
                "assembly", "set-up", "solve", "its", "MiB/rank", "peak/rank", "method");
  for (int target : tets) {
    Cantilever c = make_cantilever(4.0, cantilever_cells(target, 4.0), MaterialKind::linear);
    const Vector p = cantilever_parameters(c, 1000.0, 0.3);
    const Vector y = c.model->elimination().restrict_state(c.rest);
    const Vector b = Vector::Ones(y.size());
    std::vector<double> assembly, setup, solve;
    int iterations = 0;
    double residual = 0.0;
    std::string method = "cholmod";
    double rss = 0.0;
    long long slots = 0;
    if (mode == "cholmod") {
      ReducedAssembler assembler(*c.model);
      SparseMatrix h = assembler.hessian_pattern_matrix();
      SparseCholesky cholesky;
      for (int r = 0; r < repeats; ++r) {
        auto t0 = Clock::now();
        assembler.evaluate(y, p, nullptr, nullptr, &h, HessianMode::exact);
        assembly.push_back(seconds_since(t0));
        t0 = Clock::now();
        if (r == 0) cholesky.analyze(h);
        if (!cholesky.factorize(h).success) {
          std::fprintf(stderr, "the factorization failed\n");
          return 1;
        }
        setup.push_back(seconds_since(t0));
        t0 = Clock::now();
        const Vector x = cholesky.solve(b);
        solve.push_back(seconds_since(t0));
        residual = (b - h.selfadjointView<Eigen::Upper>() * x).norm() / b.norm();
      }
      slots = static_cast<long long>(assembler.num_slots());
      rss = status_mib("VmRSS");
    } else {
      PetscLinearSolver solver;
      if (!no_modes) solver.set_vertex_coordinates(3, y);
      std::optional<ReducedAssembler> whole;
      std::optional<HessianShare> share;
      SparseMatrix h;
      if (mode == "replicated") {
        whole.emplace(*c.model);
        h = whole->hessian_pattern_matrix();
        slots = static_cast<long long>(whole->num_slots());
      } else {
        share.emplace(*c.model, solver);
        slots = static_cast<long long>(share->num_slots());
      }
      for (int r = 0; r < repeats; ++r) {
        std::string message;
        MPI_Barrier(MPI_COMM_WORLD);
        auto t0 = Clock::now();
        if (whole)
          whole->evaluate(y, p, nullptr, nullptr, &h, HessianMode::exact);
        else
          share->assemble(y, p, HessianMode::exact);
        assembly.push_back(seconds_since(t0));
        MPI_Barrier(MPI_COMM_WORLD);
        t0 = Clock::now();
        const bool ready = whole ? solver.setup(h, message) : solver.setup_share(share->hessian(), message);
        if (!ready) {
          std::fprintf(stderr, "set-up failed: %s\n", message.c_str());
          return 1;
        }
        setup.push_back(seconds_since(t0));
        Vector x;
        MPI_Barrier(MPI_COMM_WORLD);
        t0 = Clock::now();
        const LinearSolveStats stats = solver.solve(b, 1e-10, x);
        solve.push_back(seconds_since(t0));
        iterations = stats.iterations;
        residual = stats.relative_residual;
      }
      method = solver.method() + (solver.info().near_null_space ? " + rigid-body modes" : "");
      rss = status_mib("VmRSS");
    }
    const std::vector<double> rss_per_rank = gather(rss), peak_per_rank = gather(status_mib("VmHWM"));
    const std::vector<double> slots_per_rank = gather(static_cast<double>(slots));
    if (rank != 0) continue;
    Json row;
    row["tets"] = c.mesh.num_elements();
    row["unknowns"] = y.size();
    row["assembly_seconds"] = median(assembly);
    row["setup_seconds"] = median(setup);
    row["solve_seconds"] = median(solve);
    row["iterations"] = iterations;
    row["relative_residual"] = residual;
    row["method"] = method;
    row["rss_mib_per_rank"] = array(rss_per_rank);
    row["peak_mib_per_rank"] = array(peak_per_rank);
    row["hessian_slots_per_rank"] = array(slots_per_rank);
    rows.push_back(row);
    std::printf("%-10s %5d %8d %8d | %9.3f %9.3f %9.3f %5d | %11.0f %11.0f  %s\n", mode.c_str(), ranks,
                c.mesh.num_elements(), static_cast<int>(y.size()), median(assembly), median(setup),
                median(solve), iterations, max_of(rss_per_rank), max_of(peak_per_rank), method.c_str());
    std::fflush(stdout);
  }
  if (rank == 0) {
    json["rows"] = rows;
    if (!write_report(out, json, "petsc_scaling_bench")) return 1;
  }
  return 0;
}
