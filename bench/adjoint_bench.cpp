// Cost of one gradient of a static inverse problem as a ratio of one forward solve from rest.
//
// Scene: a unit block of n^3 * 6 tets, clamped at its base, sheared and compressed by a
// traction on its top face; design variables: the Young's modulus of every tet; objective:
// target positions of the top-face vertices. For a Neo-Hookean and a linear material:
//   forward   the first J(z): Newton from rest (analysis, assembly, factorizations),
//   gradient  dJ/dz at the same z: adjoint solve + (d2E/dxdp)^T lambda + objective terms,
//   ratio     gradient / forward,
// and, as the error this speed costs, the relative difference between the gradient from
// the preconditioned-CG adjoint (default) and from a fresh factorization at x*.
// Writes JSON (--out, default bench_adjoint.json) and prints a table.
//
// usage: adjoint_bench [--tets 50000] [--out FILE]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "adjoint/static_functional.hpp"
#include "bench_cli.hpp"
#include "loaded_block.hpp"
#include "objectives/target_positions.hpp"
#include "tailor_version.hpp"

namespace tailor::bench::adjoint_bench {

using namespace tailor;

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct Row {
  std::string material;
  int tets = 0, design = 0, newton_iterations = 0, cg_iterations = 0;
  std::string method;
  double forward = 0, gradient = 0, ratio = 0, fresh_gradient = 0, difference = 0;
};

Row run(MaterialKind kind, int target_tets) {
  const bench::LoadedBlock block = bench::make_loaded_block(target_tets, kind);
  const Mesh& mesh = block.mesh;
  const Model& model = *block.model;
  const int m = mesh.num_elements();
  const Vector& base = block.parameters;
  const std::vector<int>& top_vertices = block.top_vertices;
  const auto map = embed_blocks(base, {{0, identity_map(m)}});
  Matrix targets(top_vertices.size(), 3);
  for (std::size_t k = 0; k < top_vertices.size(); ++k)
    targets.row(k) = mesh.rest_positions.row(top_vertices[k]) + Eigen::RowVector3d(0.02, 0.0, -0.03);
  const auto objective = std::make_shared<TargetPositions>(3, top_vertices, targets);
  const Vector z = base.head(m);
  const Vector y0 = block.rest_unknowns();

  Row row;
  row.material = to_string(kind);
  row.tets = m;
  row.design = m;
  StaticFunctional f(model, map, objective, y0);
  auto t0 = Clock::now();
  f.value(z);
  row.forward = seconds_since(t0);
  row.newton_iterations = f.last_newton().iterations;
  Vector g;
  t0 = Clock::now();
  f.value_and_gradient(z, g);
  row.gradient = seconds_since(t0);
  row.ratio = row.gradient / row.forward;
  row.method = to_string(f.last_hessian_solve());
  row.cg_iterations = f.last_cg_iterations();

  // Reference: the adjoint by a fresh factorization of the exact Hessian at x*.
  StaticFunctionalOptions fresh_options;
  fresh_options.max_cg_iterations = 0;
  fresh_options.linear_relative_tolerance = 0.0;
  StaticFunctional fresh(model, map, objective, y0, fresh_options);
  fresh.value(z);
  Vector g_ref;
  t0 = Clock::now();
  fresh.value_and_gradient(z, g_ref);
  row.fresh_gradient = seconds_since(t0);
  row.difference = (g - g_ref).norm() / g_ref.norm();
  return row;
}

}  // namespace

int run(int argc, char** argv) {
  int tets = 50000;
  std::string out = "bench_adjoint.json";
  bench::Cli cli("adjoint_bench", "Cost of one gradient of a static inverse problem / one forward solve.");
  cli.tets(tets);
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  std::printf("tailor %s: gradient cost / forward cost, per-element Young's moduli as design variables\n",
              version_string);
  std::printf("%-12s %7s %6s %9s %9s %7s %-20s %4s %11s %10s\n", "material", "tets", "newton", "forward",
              "gradient", "ratio", "adjoint solve", "cg", "fresh fact.", "rel. diff");
  std::vector<Row> rows;
  for (MaterialKind kind : {MaterialKind::neo_hookean, MaterialKind::linear}) {
    const Row r = run(kind, tets);
    rows.push_back(r);
    std::printf("%-12s %7d %6d %9.4f %9.4f %7.4f %-20s %4d %11.4f %10.2e\n", r.material.c_str(), r.tets,
                r.newton_iterations, r.forward, r.gradient, r.ratio, r.method.c_str(), r.cg_iterations,
                r.fresh_gradient, r.difference);
    std::fflush(stdout);
  }
  std::printf(
      "(seconds; ratio = gradient / forward; fresh fact. = gradient time with a fresh factorization at x*;\n"
      " rel. diff = |g_cg - g_fresh| / |g_fresh|)\n");
  bench::Json json = bench::report("adjoint_gradient");
  bench::Json results = bench::Json::array();
  for (const Row& r : rows)
    results.push_back({{"material", r.material},
                       {"tets", r.tets},
                       {"design_variables", r.design},
                       {"newton_iterations", r.newton_iterations},
                       {"forward_s", r.forward},
                       {"gradient_s", r.gradient},
                       {"ratio", r.ratio},
                       {"adjoint_solve", r.method},
                       {"cg_iterations", r.cg_iterations},
                       {"fresh_factorization_gradient_s", r.fresh_gradient},
                       {"relative_difference", r.difference}});
  json["results"] = results;
  return bench::write_report(out, json, "adjoint_bench") ? 0 : 1;
}

}  // namespace tailor::bench::adjoint_bench
