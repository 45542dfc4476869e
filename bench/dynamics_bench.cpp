// Time per implicit step of a Neo-Hookean cantilever under gravity (full space), for implicit
// Euler and Newmark (average acceleration), and the cost of the time-dependent adjoint.
//
// Scene: a 4 x 1 x 1 bar of nx x n x n cells (6 tets each; 57,798 tets by default), clamped at
// x = 0, E = 1e6, nu = 0.3, density 1000, gravity 9.81 downwards, consistent mass, Rayleigh
// damping alpha = 0.5, beta = 1e-3 (K at rest), h = 0.01, released from rest. For each scheme:
// the median time per step over the run (and the min/max), Newton iterations per step, the
// split into assembly / factorization / line search, and, for the same steps, one gradient of
// the tip position at the last step with respect to per-element Young's moduli, density,
// alpha and beta (TransientFunctional), as a ratio of the forward run.
// Writes JSON (--out, default bench_dynamics.json) and prints a table.
//
// usage: dynamics_bench [--tets 58000] [--steps 10] [--reuse-factorization | --no-reuse-factorization] [--out
// FILE]
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

struct Row {
  std::string scheme;
  int tets = 0, dofs = 0, steps = 0;
  double median_step = 0, min_step = 0, max_step = 0, median_cpu = 0, newton_per_step = 0;
  double assembly = 0, factorization = 0, line_search = 0;  // per step
  double tip_drop = 0;
  double forward = 0, adjoint = 0, forward_cpu = 0, adjoint_cpu = 0;
  int factorizations = 0, cg_solves = 0;
};

Row run(TimeScheme scheme, int target_tets, int steps, FactorReuse reuse_factorization) {
  DynamicTerms terms;
  const bench::Cantilever bar = bench::make_cantilever(
      4.0, bench::cantilever_cells(target_tets, 4.0), MaterialKind::neo_hookean,
      [&](Model& model, const Mesh& mesh) {
        terms = add_dynamics_terms(
            model, mesh, DynamicsSetup{MassLumping::consistent, Eigen::Vector3d(0, 0, -9.81), true});
      });
  const Mesh& mesh = bar.mesh;
  Model& model = *bar.model;
  const Vector& rest = bar.rest;
  const std::vector<int>& tip = bar.tip_vertices;
  const int m = mesh.num_elements();
  Vector p = bench::cantilever_parameters(bar, 1e6, 0.3);
  p.segment(terms.density_offset, m).setConstant(1000.0);
  p[terms.alpha_offset] = 0.5;
  p[terms.beta_offset] = 1e-3;

  TimeIntegratorOptions options;
  options.scheme = scheme;
  options.time_step = 0.01;
  options.newton.reuse_factorization = reuse_factorization;  // CG preconditioned by the kept factor
  TimeIntegrator integrator(model, options);
  Row row;
  row.scheme = to_string(scheme);
  row.tets = m;
  row.dofs = model.elimination().num_free();
  row.steps = steps;
  DynamicState state = integrator.initial_state(rest, Vector::Zero(rest.size()), p);
  std::vector<double> times, cpu;
  int iterations = 0;
  for (int s = 0; s < steps; ++s) {
    const auto t0 = Clock::now();
    const double c0 = cpu_seconds();
    const NewtonResult r = integrator.step(state, p);
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
    std::fprintf(stderr, "  %s step %d: %.3f s, %d Newton iterations (%d factorizations, %d by CG)\n",
                 row.scheme.c_str(), s + 1, times.back(), r.iterations, r.factorizations(), cg_steps);
  }
  const SparseCholesky& factor = integrator.newton().factorization();
  std::fprintf(
      stderr, "  factorization %.2f GFlop = %.0f back-solves, %.0f flops per assembled Hessian slot\n",
      1e-9 * factor.factorization_flops(), factor.factorization_flops() / (4.0 * factor.factor_nonzeros()),
      factor.factorization_flops() / static_cast<double>(integrator.newton().assembler().num_slots()));
  row.median_step = median(times);
  row.median_cpu = median(cpu);
  row.min_step = *std::min_element(times.begin(), times.end());
  row.max_step = *std::max_element(times.begin(), times.end());
  row.newton_per_step = static_cast<double>(iterations) / steps;
  for (int v : tip) row.tip_drop = std::max(row.tip_drop, rest[3 * v + 2] - state.x[3 * v + 2]);

  // One gradient over the same steps: tip position target at the last step.
  Matrix targets(tip.size(), 3);
  for (std::size_t k = 0; k < tip.size(); ++k) targets.row(k) = mesh.rest_positions.row(tip[k]);
  auto objective = std::make_shared<KeyframeTargets>(3, tip, TrajectoryQuantity::position,
                                                     std::vector<Keyframe>{{steps, targets, 1.0}});
  TransientFunctionalOptions fo;
  fo.steps = steps;
  TransientFunctional functional(integrator, identity_map(static_cast<int>(p.size())), objective, rest,
                                 Vector::Zero(rest.size()), fo);
  Vector g;
  const double c0 = cpu_seconds();
  functional.value(p);
  const double c1 = cpu_seconds();
  functional.value_and_gradient(p, g);
  row.forward_cpu = c1 - c0;
  row.adjoint_cpu = cpu_seconds() - c1;
  const TransientStatistics& st = functional.statistics();
  row.forward = st.forward_seconds;
  row.adjoint = st.adjoint_seconds;
  row.factorizations = st.factorizations;
  row.cg_solves = st.cg_solves;
  return row;
}

}  // namespace

int run(int argc, char** argv) {
  int tets = 58000, steps = 10;
  FactorReuse reuse_factorization = FactorReuse::automatic;
  std::string out = "bench_dynamics.json";
  bench::Cli cli("dynamics_bench", "Time per implicit step of a Neo-Hookean cantilever, and its adjoint.");
  cli.tets(tets, 24);
  cli.steps(steps);
  cli.on_off(
      "--reuse-factorization", "--no-reuse-factorization",
      [&reuse_factorization](bool on) { reuse_factorization = on ? FactorReuse::on : FactorReuse::off; },
      "Newton's kept factorization as CG preconditioner whenever it can (default: where it pays)",
      "Newton factorizes every iteration");
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  std::printf(
      "tailor %s: Neo-Hookean cantilever under gravity, h = 0.01, full space, reuse_factorization %s\n",
      version_string, to_string(reuse_factorization).c_str());
  std::vector<Row> rows;
  for (TimeScheme scheme : {TimeScheme::implicit_euler, TimeScheme::newmark})
    rows.push_back(run(scheme, tets, steps, reuse_factorization));
  std::printf("%-15s %6s %6s %5s %9s %9s %9s %9s %7s %9s %9s %9s %8s %9s %8s %5s %4s\n", "scheme", "tets",
              "dofs", "steps", "median/s", "min", "max", "cpu med.", "newton", "assembly", "factor",
              "line s.", "tip drop", "adjoint", "adj/fwd", "fact", "cg");
  for (const Row& r : rows)
    std::printf(
        "%-15s %6d %6d %5d %9.3f %9.3f %9.3f %9.3f %7.2f %9.3f %9.3f %9.3f %8.4f %9.3f %8.3f %5d %4d\n",
        r.scheme.c_str(), r.tets, r.dofs, r.steps, r.median_step, r.min_step, r.max_step, r.median_cpu,
        r.newton_per_step, r.assembly, r.factorization, r.line_search, r.tip_drop, r.adjoint,
        r.adjoint_cpu / r.forward_cpu, r.factorizations, r.cg_solves);
  std::printf(
      "(seconds per step, wall clock, except cpu med. = median process CPU time per step; "
      "assembly/factor/line s.\n"
      " are per-step wall-clock averages; adjoint = wall clock of one gradient over all steps; adj/fwd = its "
      "CPU\n"
      " time over the CPU time of the forward run of the same steps)\n");
  bench::Json json = bench::report("dynamics_step");
  json["reuse_factorization"] = to_string(reuse_factorization);
  bench::Json results = bench::Json::array();
  for (const Row& r : rows)
    results.push_back({{"scheme", r.scheme},
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
                       {"adjoint_over_forward_cpu", r.adjoint_cpu / r.forward_cpu},
                       {"adjoint_factorizations", r.factorizations},
                       {"adjoint_cg_solves", r.cg_solves}});
  json["results"] = results;
  return bench::write_report(out, json, "dynamics_bench") ? 0 : 1;
}

}  // namespace tailor::bench::dynamics_bench
