// Newton iteration cost on box meshes under a Neo-Hookean load case.
//
// For each mesh size, per Newton iteration: assembly (energy + gradient + Hessian),
// numeric factorization, triangular solve, line search; and the ratio
//   (whole iteration) / (factorization + solve),
// whose floor is 1 for a direct-solver Newton method: the goal is <= 1.2 on 50k tets.
// Writes JSON (--out, default bench_newton.json) and prints a table. Medians over the
// iterations of one run.
//
// usage: newton_bench [--sizes 10000,50000,200000] [--out FILE] [--max-iterations N]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "forward/fem/elastic_term.hpp"
#include "forward/fem/loads.hpp"
#include "forward/mesh/generate.hpp"
#include "forward/solve/blas_info.hpp"
#include "forward/solve/newton.hpp"
#include "tailor_version.hpp"

using namespace tailor;

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

struct SizeResult {
  int target_tets, tets, vertices, free_dofs, iterations;
  std::string status;
  double analysis, assembly, factorization, solve, line_search, iteration, ratio, total;
  long long factor_nnz_hint;
};

SizeResult run(int target_tets, int max_iterations) {
  // Cube split into n^3 cells of 6 tets, n chosen to match the target count.
  const int n = std::max(1, static_cast<int>(std::lround(std::cbrt(target_tets / 6.0))));
  const Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1), n, n, n);
  const int m = mesh.num_elements();
  Model model(3 * mesh.num_vertices());
  model.parameter_layout().add("youngs_modulus", m);
  model.parameter_layout().add("poisson_ratio", m);
  model.add(std::make_unique<ElasticTerm<3>>(mesh, make_material<3>(MaterialKind::neo_hookean), 0, m));

  // Clamped bottom (z = 0); the top face gets a shear-and-compression traction that
  // deforms the block by roughly 20-30% (about ten Newton iterations).
  const Eigen::MatrixXi top_facets = boundary_facets_where(mesh, [](const Eigen::VectorXd& X) { return X[2] > 1 - 1e-9; });
  const double E = 1e6;
  model.add(std::make_unique<ExternalForceTerm>(traction_forces(mesh, top_facets, Eigen::Vector3d(0.05 * E, 0.0, -0.05 * E))));
  Vector rest(3 * mesh.num_vertices());
  std::vector<int> fixed;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    rest.segment<3>(3 * v) = mesh.rest_positions.row(v).transpose();
    if (mesh.rest_positions(v, 2) < 1e-9)
      for (int k = 0; k < 3; ++k) fixed.push_back(3 * v + k);
  }
  model.set_elimination(Elimination::dirichlet(fixed, rest));
  Vector p(2 * m);
  p.head(m).setConstant(E);
  p.tail(m).setConstant(0.4);

  NewtonOptions options;
  options.max_iterations = max_iterations;
  options.relative_tolerance = 1e-8;
  NewtonSolver solver(model, options);
  Vector y = model.elimination().restrict_state(rest);
  const NewtonResult r = solver.solve(p, y);

  std::vector<double> assembly, factorization, solve, line_search, iteration, ratio;
  for (const auto& it : r.history) {
    assembly.push_back(it.assembly_seconds);
    factorization.push_back(it.factorization_seconds);
    solve.push_back(it.solve_seconds);
    line_search.push_back(it.line_search_seconds);
    const double whole = it.assembly_seconds + it.factorization_seconds + it.solve_seconds + it.line_search_seconds;
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
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> sizes = {10000, 50000, 200000};
  std::string out = "bench_newton.json";
  int max_iterations = 50;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--sizes" && i + 1 < argc) {
      sizes.clear();
      std::stringstream list(argv[++i]);
      for (std::string item; std::getline(list, item, ',');) sizes.push_back(std::stoi(item));
    } else if (arg == "--out" && i + 1 < argc) {
      out = argv[++i];
    } else if (arg == "--max-iterations" && i + 1 < argc) {
      max_iterations = std::stoi(argv[++i]);
    } else {
      std::cerr << "usage: newton_bench [--sizes 10000,50000,200000] [--out FILE] [--max-iterations N]\n";
      return 2;
    }
  }
  const std::string blas = blas_library_path();
  std::printf("tailor %s, Newton on a Neo-Hookean block (clamped base, shear + compression on top)\n",
              version_string);
  std::printf("BLAS: %s, hardware threads: %u\n", blas.c_str(), std::thread::hardware_concurrency());
  std::printf("%8s %9s %6s %-10s %9s %9s %9s %9s %9s %7s\n", "tets", "free DOFs", "iters", "status", "assembly",
              "factor", "solve", "l.search", "iter", "ratio");
  std::vector<SizeResult> results;
  for (int size : sizes) {
    const SizeResult s = run(size, max_iterations);
    results.push_back(s);
    std::printf("%8d %9d %6d %-10s %9.4f %9.4f %9.4f %9.4f %9.4f %7.3f\n", s.tets, s.free_dofs, s.iterations,
                s.status.c_str(), s.assembly, s.factorization, s.solve, s.line_search, s.iteration, s.ratio);
    std::fflush(stdout);
  }
  std::printf("(seconds, medians over Newton iterations; ratio = iteration / (factorization + solve))\n");

  std::ofstream json(out);
  json << "{\n  \"benchmark\": \"newton_iteration\",\n  \"tailor_version\": \"" << version_string
       << "\",\n  \"blas\": \"" << blas << "\",\n  \"hardware_threads\": " << std::thread::hardware_concurrency()
       << ",\n  \"material\": \"neo_hookean\",\n  \"results\": [\n";
  for (std::size_t k = 0; k < results.size(); ++k) {
    const auto& s = results[k];
    json << "    {\"tets\": " << s.tets << ", \"vertices\": " << s.vertices << ", \"free_dofs\": " << s.free_dofs
         << ", \"iterations\": " << s.iterations << ", \"status\": \"" << s.status << "\", \"analysis_s\": " << s.analysis
         << ", \"median_assembly_s\": " << s.assembly << ", \"median_factorization_s\": " << s.factorization
         << ", \"median_solve_s\": " << s.solve << ", \"median_line_search_s\": " << s.line_search
         << ", \"median_iteration_s\": " << s.iteration << ", \"median_ratio\": " << s.ratio
         << ", \"total_s\": " << s.total << "}" << (k + 1 < results.size() ? "," : "") << "\n";
  }
  json << "  ]\n}\n";
  std::printf("wrote %s\n", out.c_str());
  return 0;
}
