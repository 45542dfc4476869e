// Newton iteration cost on box meshes under a Neo-Hookean load case (bench/loaded_block.hpp).
//
// For each mesh size, per Newton iteration: assembly (energy + gradient + Hessian),
// numeric factorization, triangular solve, line search; and the ratio
//   (whole iteration) / (factorization + solve),
// whose floor is 1 for a direct-solver Newton method: the goal is <= 1.2 on 50k tets.
// Writes JSON (--out, default bench_newton.json) and prints a table. Medians over the
// iterations of one run.
//
// usage: newton_bench [--tets 10000,50000,200000] [--out FILE] [--max-iterations N]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "bench_cli.hpp"
#include "forward/core/statistics.hpp"
#include "forward/solve/blas_info.hpp"
#include "forward/solve/newton.hpp"
#include "loaded_block.hpp"
#include "tailor_version.hpp"

namespace tailor::bench::newton_bench {

using namespace tailor;

namespace {

struct SizeResult {
  int target_tets, tets, vertices, free_dofs, iterations;
  std::string status;
  double analysis, assembly, factorization, solve, line_search, iteration, ratio, total;
  // What FactorReuse::automatic decides by (NewtonOptions): the factorization's flops per
  // back-solve (4 nnz(L)) and per assembled Hessian slot.
  double factor_flops, factor_over_solve, flops_per_slot;
};

SizeResult run(int target_tets, int max_iterations) {
  const bench::LoadedBlock block = bench::make_loaded_block(target_tets, MaterialKind::neo_hookean);
  const Mesh& mesh = block.mesh;
  const Model& model = *block.model;
  const int m = mesh.num_elements();
  const Vector& p = block.parameters;

  NewtonOptions options;
  options.max_iterations = max_iterations;
  options.relative_tolerance = 1e-8;
  NewtonSolver solver(model, options);
  Vector y = block.rest_unknowns();
  const NewtonResult r = solver.solve(p, y);

  std::vector<double> assembly, factorization, solve, line_search, iteration, ratio;
  for (const auto& it : r.history) {
    assembly.push_back(it.assembly_seconds);
    factorization.push_back(it.factorization_seconds);
    solve.push_back(it.solve_seconds);
    line_search.push_back(it.line_search_seconds);
    const double whole =
        it.assembly_seconds + it.factorization_seconds + it.solve_seconds + it.line_search_seconds;
    iteration.push_back(whole);
    ratio.push_back(whole / (it.factorization_seconds + it.solve_seconds));
  }
  SizeResult s{};
  s.target_tets = target_tets;
  s.tets = m;
  s.vertices = mesh.num_vertices();
  s.free_dofs = model.elimination().num_free();
  s.iterations = r.iterations;
  s.status = to_string(r.status);
  s.analysis = r.analysis_seconds;
  s.assembly = median(assembly);
  s.factorization = median(factorization);
  s.solve = median(solve);
  s.line_search = median(line_search);
  s.iteration = median(iteration);
  s.ratio = median(ratio);
  s.total = r.total_seconds;
  s.factor_flops = solver.factorization().factorization_flops();
  s.factor_over_solve = s.factor_flops / (4.0 * solver.factorization().factor_nonzeros());
  s.flops_per_slot = s.factor_flops / static_cast<double>(solver.assembler().num_slots());
  return s;
}

}  // namespace

int run(int argc, char** argv) {
  std::vector<int> sizes = {10000, 50000, 200000};
  std::string out = "bench_newton.json";
  int max_iterations = 50;
  bench::Cli cli("newton_bench", "Newton iteration cost on Neo-Hookean box meshes.");
  cli.tets(sizes);
  cli.out(out);
  cli.integer("--max-iterations", max_iterations, "Newton iteration cap", 1);
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  const std::string blas = blas_library_path();
  std::printf("tailor %s, Newton on a Neo-Hookean block (clamped base, shear + compression on top)\n",
              version_string);
  std::printf("BLAS: %s, hardware threads: %u\n", blas.c_str(), std::thread::hardware_concurrency());
  std::printf("%8s %9s %6s %-10s %9s %9s %9s %9s %9s %7s %8s %8s %8s\n", "tets", "free DOFs", "iters",
              "status", "assembly", "factor", "solve", "l.search", "iter", "ratio", "GFlop", "f/solve",
              "f/slot");
  std::vector<SizeResult> results;
  for (int size : sizes) {
    const SizeResult s = run(size, max_iterations);
    results.push_back(s);
    std::printf("%8d %9d %6d %-10s %9.4f %9.4f %9.4f %9.4f %9.4f %7.3f %8.2f %8.0f %8.0f\n", s.tets,
                s.free_dofs, s.iterations, s.status.c_str(), s.assembly, s.factorization, s.solve,
                s.line_search, s.iteration, s.ratio, 1e-9 * s.factor_flops, s.factor_over_solve,
                s.flops_per_slot);
    std::fflush(stdout);
  }
  std::printf(
      "(seconds, medians over Newton iterations; ratio = iteration / (factorization + solve); GFlop, "
      "f/solve, "
      "f/slot:\n the factorization's flops, per back-solve (4 nnz(L)) and per assembled Hessian slot)\n");

  bench::Json json = bench::report("newton_iteration");
  json["blas"] = blas;
  json["hardware_threads"] = std::thread::hardware_concurrency();
  json["material"] = "neo_hookean";
  bench::Json rows = bench::Json::array();
  for (const SizeResult& s : results)
    rows.push_back({{"tets", s.tets},
                    {"vertices", s.vertices},
                    {"free_dofs", s.free_dofs},
                    {"iterations", s.iterations},
                    {"status", s.status},
                    {"analysis_s", s.analysis},
                    {"median_assembly_s", s.assembly},
                    {"median_factorization_s", s.factorization},
                    {"median_solve_s", s.solve},
                    {"median_line_search_s", s.line_search},
                    {"median_iteration_s", s.iteration},
                    {"median_ratio", s.ratio},
                    {"total_s", s.total},
                    {"factorization_flops", s.factor_flops},
                    {"factorization_over_solve_flops", s.factor_over_solve},
                    {"factorization_flops_per_slot", s.flops_per_slot}});
  json["results"] = rows;
  return bench::write_report(out, json, "newton_bench") ? 0 : 1;
}

}  // namespace tailor::bench::newton_bench
