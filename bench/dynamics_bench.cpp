// Time per implicit step of a cantilever under gravity (full space), for implicit Euler and
// Newmark (average acceleration), and the cost of the time-dependent adjoint against its forward
// run.
//
// Scene: a 4 x 1 x 1 bar of nx x n x n cells (6 tets each; 57,798 tets by default), clamped at
// x = 0, Neo-Hookean (default) or linear material (--materials), E = 1e6, nu = 0.3, density
// 1000, gravity 9.81 downwards, consistent mass, Rayleigh damping alpha = 0.5, beta = 1e-3 (K at
// rest), h = 0.01, released from rest. For each material and scheme: the median time per step
// over the run (and the min/max), Newton iterations per step, the split into assembly /
// factorization / line search, and, for the same steps, one gradient of the tip position at the
// last step with respect to per-element Young's moduli, density, alpha and beta
// (TransientFunctional): its CPU time over that of the forward run (value() alone), the sparse
// Cholesky work of each (numeric factorizations, back-solved right-hand sides), and where the
// adjoint's time went.
// Writes JSON (--out, default bench_dynamics.json) and prints two tables.
//
// usage: dynamics_bench [--tets 58000] [--steps 10] [--materials neo_hookean,linear]
//        [--reuse-factorization | --no-reuse-factorization] [--no-stored-hessians] [--out FILE]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "adjoint/transient_functional.hpp"
#include "bench_cli.hpp"
#include "cantilever.hpp"
#include "forward/dynamics/setup.hpp"
#include "tailor_version.hpp"

namespace tailor::bench::dynamics_bench {

using namespace tailor;

namespace {

using bench::Clock;
using bench::cpu_seconds;
using bench::median;
using bench::seconds_since;

struct Settings {
  int tets = 58000, steps = 10;
  FactorReuse reuse_factorization = FactorReuse::automatic;
  bool stored_hessians = true;  // TransientFunctionalOptions::stored_hessian_megabytes > 0
};

struct Row {
  std::string material, scheme;
  int tets = 0, dofs = 0, steps = 0;
  double median_step = 0, min_step = 0, max_step = 0, median_cpu = 0, newton_per_step = 0;
  double assembly = 0, factorization = 0, line_search = 0;  // per step
  double tip_drop = 0;
  // The gradient over the same steps: forward run (value()) and backward pass.
  double forward = 0, adjoint = 0, forward_cpu = 0, adjoint_cpu = 0;
  TransientStatistics stats;
  double ratio() const { return forward_cpu > 0 ? adjoint_cpu / forward_cpu : 0.0; }
};

struct Scene {
  DynamicTerms terms;
  bench::Cantilever bar;
  Vector p;
};

// The cantilever with its dynamics terms and parameters.
Scene make_scene(int target_tets, MaterialKind material) {
  Scene scene;
  scene.bar = bench::make_cantilever(
      4.0, bench::cantilever_cells(target_tets, 4.0), material, [&](Model& model, const Mesh& mesh) {
        scene.terms = add_dynamics_terms(
            model, mesh, DynamicsSetup{MassLumping::consistent, Eigen::Vector3d(0, 0, -9.81), true});
      });
  const int m = scene.bar.mesh.num_elements();
  scene.p = bench::cantilever_parameters(scene.bar, 1e6, 0.3);
  scene.p.segment(scene.terms.density_offset, m).setConstant(1000.0);
  scene.p[scene.terms.alpha_offset] = 0.5;
  scene.p[scene.terms.beta_offset] = 1e-3;
  return scene;
}

// Times `steps` implicit steps from rest, one by one.
void time_steps(TimeIntegrator& integrator, const Scene& scene, int steps, Row& row) {
  const Vector& rest = scene.bar.rest;
  DynamicState state = integrator.initial_state(rest, Vector::Zero(rest.size()), scene.p);
  std::vector<double> times, cpu;
  int iterations = 0;
  for (int s = 0; s < steps; ++s) {
    const auto t0 = Clock::now();
    const double c0 = cpu_seconds();
    const NewtonResult r = integrator.step(state, scene.p);
    times.push_back(seconds_since(t0));
    cpu.push_back(cpu_seconds() - c0);
    if (!r.converged()) throw std::runtime_error("step " + std::to_string(s + 1) + " failed: " + r.message);
    iterations += r.iterations;
    int cg_steps = 0;
    for (const auto& it : r.history) {
      cg_steps += it.reused_factorization ? 1 : 0;
      row.assembly += it.assembly_seconds / steps;
      row.factorization += it.factorization_seconds / steps;
      row.line_search += it.line_search_seconds / steps;
    }
    std::fprintf(stderr, "  %s %s step %d: %.3f s, %d Newton iterations (%d factorizations, %d by CG)\n",
                 row.material.c_str(), row.scheme.c_str(), s + 1, times.back(), r.iterations,
                 r.factorizations(), cg_steps);
  }
  const SparseCholesky& factor = integrator.newton().factorization();
  if (factor.factor_nonzeros() > 0)
    std::fprintf(
        stderr, "  factorization %.2f GFlop = %.0f back-solves, %.0f flops per assembled Hessian slot\n",
        1e-9 * factor.factorization_flops(), factor.factorization_flops() / (4.0 * factor.factor_nonzeros()),
        factor.factorization_flops() / static_cast<double>(integrator.newton().assembler().num_slots()));
  row.median_step = median(times);
  row.median_cpu = median(cpu);
  row.min_step = *std::min_element(times.begin(), times.end());
  row.max_step = *std::max_element(times.begin(), times.end());
  row.newton_per_step = static_cast<double>(iterations) / steps;
  for (int v : scene.bar.tip_vertices)
    row.tip_drop = std::max(row.tip_drop, rest[3 * v + 2] - state.x[3 * v + 2]);
}

// One gradient over the same steps (tip position target at the last step): CPU time of the
// forward run (value()) and of the backward pass (value_and_gradient() at the same point).
void time_gradient(TimeIntegrator& integrator, const Scene& scene, const Settings& settings, Row& row) {
  const Mesh& mesh = scene.bar.mesh;
  const std::vector<int>& tip = scene.bar.tip_vertices;
  Matrix targets(tip.size(), 3);
  for (std::size_t k = 0; k < tip.size(); ++k) targets.row(k) = mesh.rest_positions.row(tip[k]);
  auto objective = std::make_shared<KeyframeTargets>(3, tip, TrajectoryQuantity::position,
                                                     std::vector<Keyframe>{{settings.steps, targets, 1.0}});
  TransientFunctionalOptions fo;
  fo.steps = settings.steps;
  if (!settings.stored_hessians) fo.stored_hessian_megabytes = 0.0;
  TransientFunctional functional(integrator, identity_map(static_cast<int>(scene.p.size())), objective,
                                 scene.bar.rest, Vector::Zero(scene.bar.rest.size()), fo);
  Vector g;
  const double c0 = cpu_seconds();
  functional.value(scene.p);
  const double c1 = cpu_seconds();
  functional.value_and_gradient(scene.p, g);
  row.forward_cpu = c1 - c0;
  row.adjoint_cpu = cpu_seconds() - c1;
  row.stats = functional.statistics();
  row.forward = row.stats.forward_seconds;
  row.adjoint = row.stats.adjoint_seconds;
}

Row run(MaterialKind material, TimeScheme scheme, const Settings& settings) {
  const Scene scene = make_scene(settings.tets, material);
  TimeIntegratorOptions options;
  options.scheme = scheme;
  options.time_step = 0.01;
  options.newton.reuse_factorization = settings.reuse_factorization;  // CG preconditioned by the kept factor
  TimeIntegrator integrator(*scene.bar.model, options);
  Row row;
  row.material = std::string(material.name());
  row.scheme = to_string(scheme);
  row.tets = scene.bar.mesh.num_elements();
  row.dofs = scene.bar.model->elimination().num_free();
  row.steps = settings.steps;
  time_steps(integrator, scene, settings.steps, row);
  time_gradient(integrator, scene, settings, row);
  return row;
}

void print_tables(const std::vector<Row>& rows) {
  std::printf("%-12s %-15s %6s %6s %5s %9s %9s %9s %9s %7s %9s %9s %9s %8s\n", "material", "scheme", "tets",
              "dofs", "steps", "median/s", "min", "max", "cpu med.", "newton", "assembly", "factor",
              "line s.", "tip drop");
  for (const Row& r : rows)
    std::printf("%-12s %-15s %6d %6d %5d %9.3f %9.3f %9.3f %9.3f %7.2f %9.3f %9.3f %9.3f %8.4f\n",
                r.material.c_str(), r.scheme.c_str(), r.tets, r.dofs, r.steps, r.median_step, r.min_step,
                r.max_step, r.median_cpu, r.newton_per_step, r.assembly, r.factorization, r.line_search,
                r.tip_drop);
  std::printf(
      "(seconds per step, wall clock, except cpu med. = median process CPU time per step; "
      "assembly/factor/line s.\n"
      " are per-step wall-clock averages)\n\n");
  std::printf("%-12s %-15s %8s %8s %8s %5s %6s %5s %6s %5s %5s %6s %7s %7s %7s %7s\n", "material", "scheme",
              "fwd cpu", "adj cpu", "adj/fwd", "fwd f", "fwd bs", "adj f", "adj bs", "H asm", "H kept",
              "cg it", "asm s", "fact s", "solve s", "dp s");
  for (const Row& r : rows) {
    const TransientStatistics& st = r.stats;
    std::printf("%-12s %-15s %8.3f %8.3f %8.3f %5ld %6ld %5ld %6ld %5d %6d %5d %7.3f %7.3f %7.3f %7.3f\n",
                r.material.c_str(), r.scheme.c_str(), r.forward_cpu, r.adjoint_cpu, r.ratio(),
                st.forward_factorizations, st.forward_back_solves, st.adjoint_numeric_factorizations,
                st.adjoint_back_solves, st.hessian_assemblies, st.stored_hessians_used, st.cg_iterations,
                st.adjoint_assembly_seconds, st.adjoint_factorization_seconds, st.adjoint_solve_seconds,
                st.adjoint_products_seconds);
  }
  std::printf(
      "(one gradient over all steps: fwd cpu / adj cpu = process CPU seconds of the forward run (value()) "
      "and\n"
      " of the backward pass; adj/fwd their ratio; f = numeric factorizations, bs = back-solved right-hand\n"
      " sides; H asm = step Hessians assembled by the adjoint, H kept = taken from the forward's copies;\n"
      " cg it = CG iterations; asm/fact/solve/dp s = adjoint wall seconds in Hessian assembly, "
      "factorization,\n"
      " solves, parameter-derivative products)\n");
}

bench::Json to_json(const Row& r) {
  const TransientStatistics& st = r.stats;
  return {{"material", r.material},
          {"scheme", r.scheme},
          {"tets", r.tets},
          {"dofs", r.dofs},
          {"steps", r.steps},
          {"median_step_s", r.median_step},
          {"min_step_s", r.min_step},
          {"max_step_s", r.max_step},
          {"median_step_cpu_s", r.median_cpu},
          {"newton_iterations_per_step", r.newton_per_step},
          {"assembly_s_per_step", r.assembly},
          {"factorization_s_per_step", r.factorization},
          {"line_search_s_per_step", r.line_search},
          {"tip_drop", r.tip_drop},
          {"forward_s", r.forward},
          {"adjoint_s", r.adjoint},
          {"forward_cpu_s", r.forward_cpu},
          {"adjoint_cpu_s", r.adjoint_cpu},
          {"adjoint_over_forward_cpu", r.ratio()},
          {"forward_factorizations", st.forward_factorizations},
          {"forward_back_solves", st.forward_back_solves},
          {"adjoint_factorizations", st.factorizations},
          {"adjoint_numeric_factorizations", st.adjoint_numeric_factorizations},
          {"adjoint_back_solves", st.adjoint_back_solves},
          {"adjoint_cg_solves", st.cg_solves},
          {"adjoint_cg_iterations", st.cg_iterations},
          {"adjoint_kept_factor_solves", st.kept_factor_solves},
          {"adjoint_hessian_assemblies", st.hessian_assemblies},
          {"adjoint_stored_hessians_used", st.stored_hessians_used},
          {"stored_hessian_megabytes_peak", st.stored_hessian_megabytes_peak},
          {"adjoint_assembly_s", st.adjoint_assembly_seconds},
          {"adjoint_factorization_s", st.adjoint_factorization_seconds},
          {"adjoint_solve_s", st.adjoint_solve_seconds},
          {"adjoint_products_s", st.adjoint_products_seconds},
          {"adjoint_newmark_start_s", st.adjoint_start_seconds},
          {"max_preconditioner_residual", st.max_preconditioner_residual}};
}

}  // namespace

int run(int argc, char** argv) {
  Settings settings;
  std::vector<std::string> materials{"neo_hookean"};
  std::string out = "bench_dynamics.json";
  bench::Cli cli("dynamics_bench",
                 "Time per implicit step of a cantilever, and its adjoint against its forward run.");
  cli.tets(settings.tets, 24);
  cli.steps(settings.steps);
  cli.choices("--materials", materials, "materials of the bar", {"neo_hookean", "linear"});
  cli.on_off(
      "--reuse-factorization", "--no-reuse-factorization",
      [&settings](bool on) { settings.reuse_factorization = on ? FactorReuse::on : FactorReuse::off; },
      "Newton's kept factorization as CG preconditioner whenever it can (default: where it pays)",
      "Newton factorizes every iteration");
  cli.flag(
      "--no-stored-hessians", [&settings] { settings.stored_hessians = false; },
      "the adjoint assembles every step Hessian (default: it takes the forward pass's copies)");
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  std::printf("tailor %s: cantilever under gravity, h = 0.01, full space, reuse_factorization %s%s\n",
              version_string, to_string(settings.reuse_factorization).c_str(),
              settings.stored_hessians ? "" : ", adjoint without stored Hessians");
  std::vector<Row> rows;
  for (const std::string& material : materials)
    for (TimeScheme scheme : {TimeScheme::implicit_euler, TimeScheme::newmark})
      rows.push_back(run(parse_material_kind(material), scheme, settings));
  print_tables(rows);
  bench::Json json = bench::report("dynamics_step");
  json["reuse_factorization"] = to_string(settings.reuse_factorization);
  json["stored_hessians"] = settings.stored_hessians;
  bench::Json results = bench::Json::array();
  for (const Row& r : rows) results.push_back(to_json(r));
  json["results"] = results;
  return bench::write_report(out, json, "dynamics_bench") ? 0 : 1;
}

}  // namespace tailor::bench::dynamics_bench
