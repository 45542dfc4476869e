// Newton iteration cost of a discrete elastic rod against its vertex count (should be linear:
// the Hessian is banded). A helical rod of length 1 (EI = 1, circular section r = 1e-2) clamped
// at its first edge sags under gravity (total weight 2); Newton runs a fixed number of
// iterations and the medians of the per-iteration times are reported: assembly (energy,
// gradient, Hessian of the stretching, bending, twisting and load terms), factorization,
// solve, line search, and the whole iteration. Writes JSON (--out, default bench_rods.json)
// and prints a table.
//
// usage: rod_bench [--vertices 100,1000,10000,100000] [--iterations N] [--out FILE]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "forward/core/elimination.hpp"
#include "forward/core/statistics.hpp"
#include "forward/fem/loads.hpp"
#include "forward/rods/bending_term.hpp"
#include "forward/rods/rod_supports.hpp"
#include "forward/rods/stretching_term.hpp"
#include "forward/rods/twisting_term.hpp"
#include "forward/solve/newton.hpp"

using namespace tailor;

namespace {

struct SizeResult {
  int vertices, free_dofs, iterations;
  std::string status;
  double assembly, factorization, solve, line_search, iteration;
};

SizeResult run(int vertices, int iterations) {
  Eigen::MatrixX3d positions(vertices, 3);
  for (int i = 0; i < vertices; ++i) {
    const double s = double(i) / (vertices - 1), phi = 4.0 * M_PI * s;
    positions.row(i) << s, 0.05 * std::cos(phi), 0.05 * std::sin(phi);
  }
  auto rod = std::make_shared<DiscreteRod>(positions, 0, 3 * vertices, Eigen::Vector3d::UnitZ());
  Model model(rod->dof_end());
  RodMaterial material;
  material.radius = 1e-2;
  material.youngs_modulus = 4.0 / (M_PI * std::pow(material.radius, 4));
  material.shear_modulus = material.youngs_modulus / 2.6;
  const RodParameterBlocks blocks = add_rod_parameters(model.parameter_layout(), *rod);
  Vector p = Vector::Zero(model.parameter_layout().size());
  write_rod_parameters(*rod, blocks, material, p);
  model.add(std::make_unique<RodStretchingTerm>(rod, material.section, blocks));
  model.add(std::make_unique<RodBendingTerm>(rod, material.section, blocks));
  model.add(std::make_unique<RodTwistingTerm>(rod, material.section, blocks));
  const double area = M_PI * material.radius * material.radius, g = 9.81;
  const Eigen::VectorXd masses = lumped_vertex_masses(*rod, material.section, 2.0 / (area * g),
                                                      p.segment(blocks.radius, rod->num_edges()),
                                                      p.segment(blocks.rest_length, rod->num_edges()));
  Vector forces = Vector::Zero(model.num_dofs());
  add_gravity_forces(*rod, masses, Eigen::Vector3d(0, -g, 0), forces);
  model.add(std::make_unique<ExternalForceTerm>(forces, "gravity"));
  Vector rest = Vector::Zero(model.num_dofs());
  rod->write_rest_state(rest);
  model.set_elimination(Elimination::dirichlet(clamped_end_dofs(*rod, RodEnd::first), rest));

  NewtonOptions options;
  options.max_iterations = iterations;
  NewtonSolver solver(model, options);
  Vector y = model.elimination().restrict_state(rest);
  const NewtonResult r = solver.solve(p, y);
  std::vector<double> assembly, factorization, solve, line_search, iteration;
  for (const auto& it : r.history) {
    assembly.push_back(it.assembly_seconds);
    factorization.push_back(it.factorization_seconds);
    solve.push_back(it.solve_seconds);
    line_search.push_back(it.line_search_seconds);
    iteration.push_back(it.assembly_seconds + it.factorization_seconds + it.solve_seconds +
                        it.line_search_seconds);
  }
  return {vertices,         model.elimination().num_free(), r.iterations,  to_string(r.status),
          median(assembly), median(factorization),          median(solve), median(line_search),
          median(iteration)};
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> sizes = {100, 1000, 10000, 100000};
  int iterations = 5;
  std::string out = "bench_rods.json";
  bench::Cli cli("rod_bench", "Newton iteration cost of a discrete elastic rod against its vertex count.");
  cli.integers("--vertices", sizes, "vertex counts of the rod", 3);
  cli.integer("--iterations", iterations, "Newton iterations run (and timed) per size", 1);
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  std::vector<SizeResult> results;
  std::printf("%10s %10s %6s %10s %10s %10s %10s %10s %12s\n", "vertices", "free_dofs", "iters", "assembly",
              "factor", "solve", "line_srch", "iteration", "us/vertex");
  for (int n : sizes) {
    const SizeResult s = run(n, iterations);
    results.push_back(s);
    std::printf("%10d %10d %6d %10.4f %10.4f %10.4f %10.4f %10.4f %12.3f\n", s.vertices, s.free_dofs,
                s.iterations, s.assembly, s.factorization, s.solve, s.line_search, s.iteration,
                1e6 * s.iteration / s.vertices);
  }
  bench::Json json = bench::report("rod_newton_iteration");
  bench::Json rows = bench::Json::array();
  for (const SizeResult& s : results)
    rows.push_back({{"vertices", s.vertices},
                    {"free_dofs", s.free_dofs},
                    {"iterations", s.iterations},
                    {"status", s.status},
                    {"assembly_s", s.assembly},
                    {"factorization_s", s.factorization},
                    {"solve_s", s.solve},
                    {"line_search_s", s.line_search},
                    {"iteration_s", s.iteration}});
  json["sizes"] = rows;
  return bench::write_report(out, json, "rod_bench") ? 0 : 1;
}
