// Speed against error of the descent solver (forward/dynamics/descent_solver.hpp) against
// Newton on implicit Euler steps of dynamics_bench's cantilever: a 4 x 1 x 1 bar clamped at
// x = 0, Neo-Hookean, E = 1e6, nu = 0.3, density 1000, gravity, consistent mass, Rayleigh
// alpha = 0.5, beta = 1e-3, h = 0.01, released from rest (57,798 tets by default, and a
// ~150k-tet bar of the same shape).
//
// Per mesh:
//  - Newton's reference trajectory (relative tolerance 1e-10): median time per step;
//  - descent with fixed iteration budgets (the tolerance out of reach): median time per step,
//    reached relative residual, the state error against the reference (max over steps of
//    ||x - x_newton||_inf over the reference's largest displacement) and the energy drift
//    (kinetic + potential at the last step minus Newton's, over the energy change of Newton's run);
//  - matched residual: Newton and descent both to the same relative tolerance, time per step;
//  - the error at matched time: that of the largest budget whose step is not slower than Newton's;
//  - 1 and 2 threads (OpenMP) in the same run, for one budget;
//  - bytes per element per pass (BlockJacobiPass::bytes_per_pass, the arrays a pass streams)
//    and the bandwidth a pass reaches, against a measured triad bandwidth.
// Writes JSON (--out), prints tables and a PNG of error against CPU time per step (--plot;
// process CPU time, which a loaded machine inflates less than wall time).
//
// --device-table: the GPU path (docs/dynamics.md, "The GPU path") on generated bars with the
// vertex/element counts of the published table (Wang & Yang 2016: 16K/58K, 15K/55K, 14K/72K,
// 48K/158K, 96K/316K): per mesh Newton's reference, descent on the device with the vertex-block
// rule at each of --device-budgets (median wall time per step, state error against Newton) and
// the same rule on the CPU at the middle budget. Skipped, with a line saying so, without a
// usable CUDA device; the CPU rows of the default run are then left out.
//
// usage: descent_bench [--tets 58000,150000] [--steps 3] [--budgets 25,50,100,200]
//        [--threads 1,2] [--matched-tolerance 1e-3] [--out FILE] [--plot FILE]
//        [--device-table] [--device-budgets 50,100,200] [--table-on-cpu] [--table-scale 1]
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "cantilever.hpp"
#include "forward/dynamics/descent_device.hpp"
#include "forward/dynamics/descent_time_stepper.hpp"
#include "forward/dynamics/descent_vertex_blocks.hpp"
#include "forward/dynamics/setup.hpp"
#include "problems/plot/line_plot.hpp"
#include "tailor_version.hpp"

namespace tailor::bench::descent_bench {

using namespace tailor;

namespace {

using bench::Clock;
using bench::median;
using bench::seconds_since;

struct Settings {
  std::vector<int> tets{58000, 150000};
  int steps = 3;
  std::vector<int> budgets{25, 50, 100, 200};
  std::vector<int> threads{1, 2};
  double matched_tolerance = 1e-3;
  int matched_budget = 5000;
  bool device_table = false;
  std::vector<int> device_budgets{50, 100, 200};
  bool table_on_cpu = false;  // the table's rows with the rule on the CPU instead of the device
  double table_scale = 1.0;   // vertex and tet counts times this (a quick run of the same code)
};

struct Scene {
  DynamicTerms terms;
  bench::Cantilever bar;
  Vector p;
};

Scene make_scene(int target_tets) {
  Scene scene;
  scene.bar = bench::make_cantilever(4.0, bench::cantilever_cells(target_tets, 4.0), MaterialKind::neo_hookean,
                                     [&](Model& model, const Mesh& mesh) {
                                       scene.terms = add_dynamics_terms(
                                           model, mesh,
                                           DynamicsSetup{MassLumping::consistent, Eigen::Vector3d(0, 0, -9.81), true});
                                     });
  const int m = scene.bar.mesh.num_elements();
  scene.p = bench::cantilever_parameters(scene.bar, 1e6, 0.3);
  scene.p.segment(scene.terms.density_offset, m).setConstant(1000.0);
  scene.p[scene.terms.alpha_offset] = 0.5;
  scene.p[scene.terms.beta_offset] = 1e-3;
  return scene;
}

// The same scene on an a x b x c box of cubic cells (6 tets each), 4 m along x, clamped at x = 0.
Scene make_box_scene(int a, int b, int c) {
  Scene scene;
  const double cell = 4.0 / a;
  bench::Cantilever& bar = scene.bar;
  bar.mesh = box_tet_mesh(Eigen::Vector3d::Zero(), cell * Eigen::Vector3d(a, b, c), a, b, c);
  const int m = bar.mesh.num_elements();
  bar.model = std::make_unique<Model>(3 * bar.mesh.num_vertices());
  const int youngs = bar.model->parameter_layout().add("youngs_modulus", m);
  const int poisson = bar.model->parameter_layout().add("poisson_ratio", m);
  bar.model->add(std::make_unique<ElasticTerm<3>>(bar.mesh, make_material<3>(MaterialKind::neo_hookean), youngs, poisson));
  scene.terms = add_dynamics_terms(*bar.model, bar.mesh,
                                   DynamicsSetup{MassLumping::consistent, Eigen::Vector3d(0, 0, -9.81), true});
  bar.rest.resize(3 * bar.mesh.num_vertices());
  for (int v = 0; v < bar.mesh.num_vertices(); ++v) {
    bar.rest.segment<3>(3 * v) = bar.mesh.rest_positions.row(v).transpose();
    if (bar.mesh.rest_positions(v, 0) < 1e-9)
      for (int k = 0; k < 3; ++k) bar.fixed_dofs.push_back(3 * v + k);
  }
  bar.model->set_elimination(Elimination::dirichlet(bar.fixed_dofs, bar.rest));
  scene.p = bench::cantilever_parameters(bar, 1e6, 0.3);
  scene.p.segment(scene.terms.density_offset, m).setConstant(1000.0);
  scene.p[scene.terms.alpha_offset] = 0.5;
  scene.p[scene.terms.beta_offset] = 1e-3;
  return scene;
}

// Box cells a x b x c (a >= c >= b) whose vertex and tet counts, (a+1)(b+1)(c+1) and 6abc, are
// nearest (sum of relative errors) the targets.
std::array<int, 3> box_cells(int vertices, int tets) {
  std::array<int, 3> best{1, 1, 1};
  double best_error = 1e300;
  for (int b = 1; b <= 64; ++b)
    for (int c = b; c <= 64; ++c) {
      const int a = std::max(c, static_cast<int>(std::lround(tets / (6.0 * b * c))));
      const double error = std::abs(static_cast<double>(a + 1) * (b + 1) * (c + 1) / vertices - 1.0) +
                           std::abs(6.0 * a * b * c / tets - 1.0);
      if (error < best_error) best_error = error, best = {a, b, c};
    }
  return best;
}

TimeIntegratorOptions integrator_options(double newton_tolerance) {
  TimeIntegratorOptions o;
  o.time_step = 0.01;
  o.newton.relative_tolerance = newton_tolerance;
  return o;
}

// One run of `steps` steps: states, total energies, times, residuals (relative to the scale).
struct Trajectory {
  std::vector<Vector> x;
  std::vector<double> energy, step_s, step_cpu_s, relative_residual;
  std::vector<int> iterations;
};

Trajectory newton_run(Scene& scene, int steps, double tolerance) {
  TimeIntegrator integrator(*scene.bar.model, integrator_options(tolerance));
  const Vector& rest = scene.bar.rest;
  DynamicState s = integrator.initial_state(rest, Vector::Zero(rest.size()), scene.p);
  Trajectory t;
  for (int n = 0; n < steps; ++n) {
    const auto t0 = Clock::now();
    const double c0 = bench::cpu_seconds();
    const NewtonResult r = integrator.step(s, scene.p);
    t.step_s.push_back(seconds_since(t0));
    t.step_cpu_s.push_back(bench::cpu_seconds() - c0);
    if (!r.converged()) throw std::runtime_error("Newton step " + std::to_string(n + 1) + ": " + r.message);
    t.x.push_back(s.x);
    t.energy.push_back(integrator.kinetic_energy(s.v, scene.p) + integrator.potential_energy(s.x, scene.p));
    t.iterations.push_back(r.iterations);
    t.relative_residual.push_back(r.final_residual / std::max(s.residual_scale, 1e-300));
  }
  return t;
}

Trajectory descent_run(Scene& scene, int steps, const DescentOptions& options) {
  TimeIntegrator integrator(*scene.bar.model, integrator_options(1e-10));
  DescentTimeStepper stepper(integrator, options);
  const Vector& rest = scene.bar.rest;
  DynamicState s = integrator.initial_state(rest, Vector::Zero(rest.size()), scene.p);
  Trajectory t;
  for (int n = 0; n < steps; ++n) {
    const auto t0 = Clock::now();
    const double c0 = bench::cpu_seconds();
    const DescentResult r = stepper.step(s, scene.p);
    t.step_s.push_back(seconds_since(t0));
    t.step_cpu_s.push_back(bench::cpu_seconds() - c0);
    if (!r.usable()) throw std::runtime_error("descent step " + std::to_string(n + 1) + ": " + r.message);
    t.x.push_back(s.x);
    t.energy.push_back(integrator.kinetic_energy(s.v, scene.p) + integrator.potential_energy(s.x, scene.p));
    t.iterations.push_back(r.iterations);
    t.relative_residual.push_back(r.scale > 0 ? r.final_residual / r.scale : 0.0);
  }
  return t;
}

// max_n ||x_n - x_ref,n||_inf over the reference's largest displacement from rest.
double state_error(const Trajectory& t, const Trajectory& reference, const Vector& rest) {
  double error = 0.0, moved = 0.0;
  for (std::size_t n = 0; n < t.x.size(); ++n) {
    error = std::max(error, (t.x[n] - reference.x[n]).lpNorm<Eigen::Infinity>());
    moved = std::max(moved, (reference.x[n] - rest).lpNorm<Eigen::Infinity>());
  }
  return moved > 0 ? error / moved : error;
}

struct Row {
  std::string solver;  // "newton" or "descent"
  int budget = 0;      // descent's iteration budget (0: to the tolerance)
  int threads = 0;
  double tolerance = 0.0;
  bool scaling = false;  // a thread-scaling run (left out of the plot)
  double step_s = 0.0, step_cpu_s = 0.0, iterations = 0.0, relative_residual = 0.0, state_error = 0.0, energy_drift = 0.0;
};

Row summarize(const std::string& solver, int budget, int threads, double tolerance, const Trajectory& t,
              const Trajectory& reference, const Vector& rest) {
  Row r{solver, budget, threads, tolerance};
  r.step_s = median(std::vector<double>(t.step_s));
  r.step_cpu_s = median(std::vector<double>(t.step_cpu_s));
  double iterations = 0;
  for (int i : t.iterations) iterations += i;
  r.iterations = iterations / static_cast<double>(t.iterations.size());
  r.relative_residual = median(std::vector<double>(t.relative_residual));
  r.state_error = state_error(t, reference, rest);
  // Energy drift against Newton's at the last step, over the energy change of Newton's run.
  const double change = std::abs(reference.energy.back() - reference.energy.front()) + 1e-300;
  r.energy_drift = (t.energy.back() - reference.energy.back()) / change;
  return r;
}

// Triad a = b + s c over arrays far larger than the caches: bytes moved per second (3 arrays
// of 8-byte values per element; write-allocate traffic not counted), median of 5.
double triad_bandwidth() {
  const std::size_t n = 1u << 24;  // 128 MB per array
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  std::vector<double> rates;
  for (int r = 0; r < 5; ++r) {
    const auto t0 = Clock::now();
    const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i) a[i] = b[i] + 0.5 * c[i];
    rates.push_back(3.0 * 8.0 * static_cast<double>(n) / seconds_since(t0));
  }
  return median(rates) + 0.0 * a[n / 2];
}

struct PassCost {
  double bytes_per_element = 0.0, seconds = 0.0, cpu_seconds = 0.0, bandwidth = 0.0;
  double vertex_block_seconds = 0.0, vertex_block_cpu_seconds = 0.0;  // the vertex-block rule's pass on the CPU
};

// One pass (energy, gradient, block-Jacobi inverse) at the first step's start, median of 7.
PassCost time_pass(Scene& scene) {
  TimeIntegrator integrator(*scene.bar.model, integrator_options(1e-10));
  const Vector& rest = scene.bar.rest;
  DynamicState s = integrator.initial_state(rest, Vector::Zero(rest.size()), scene.p);
  integrator.configure_step(s, scene.p);
  BlockJacobiPass pass(*scene.bar.model, 3);
  DescentEvaluation at;
  std::vector<double> times, cpu;
  for (int r = 0; r < 8; ++r) {
    const auto t0 = Clock::now();
    const double c0 = bench::cpu_seconds();
    pass.evaluate(s.y, scene.p, at, true);
    if (r == 0) continue;  // the first writes the constant terms' blocks
    times.push_back(seconds_since(t0));
    cpu.push_back(bench::cpu_seconds() - c0);
  }
  PassCost c;
  c.seconds = median(times);
  c.cpu_seconds = median(cpu);
  // The same pass with the vertex-block rule (the device's; descent_vertex_blocks.hpp) on the host.
  VertexBlockModel rule(*scene.bar.model);
  rule.prepare(scene.p, s.y);
  VertexBlockHostPass vertex_pass(rule);
  VertexBlockHostPass::Result result;
  times.clear(), cpu.clear();
  for (int r = 0; r < 7; ++r) {
    const auto t0 = Clock::now();
    const double c0 = bench::cpu_seconds();
    vertex_pass.evaluate(s.y, result, true);
    times.push_back(seconds_since(t0));
    cpu.push_back(bench::cpu_seconds() - c0);
  }
  c.vertex_block_seconds = median(times);
  c.vertex_block_cpu_seconds = median(cpu);
  const double bytes = static_cast<double>(pass.bytes_per_pass(true));
  c.bytes_per_element = bytes / scene.bar.mesh.num_elements();
  c.bandwidth = bytes / c.seconds;
  return c;
}

struct MeshResult {
  int tets = 0, dofs = 0;
  std::vector<Row> rows;
  PassCost pass;
  double error_at_newton_time = 0.0;
  int budget_at_newton_time = 0;
};

MeshResult run_mesh(int target, const Settings& settings) {
  Scene scene = make_scene(target);
  MeshResult result;
  result.tets = scene.bar.mesh.num_elements();
  result.dofs = scene.bar.model->elimination().num_free();
  const Vector& rest = scene.bar.rest;
  const int threads = omp_get_max_threads();
  std::fprintf(stderr, "%d tets: Newton reference\n", result.tets);
  const Trajectory reference = newton_run(scene, settings.steps, 1e-10);
  result.rows.push_back(summarize("newton", 0, threads, 1e-10, reference, reference, rest));
  const double newton_step = result.rows.back().step_s;
  for (int budget : settings.budgets) {
    std::fprintf(stderr, "%d tets: descent, budget %d\n", result.tets, budget);
    DescentOptions o;
    o.relative_tolerance = 1e-14;  // out of reach: the budget decides
    o.max_iterations = budget;
    result.rows.push_back(
        summarize("descent", budget, threads, 0.0, descent_run(scene, settings.steps, o), reference, rest));
    if (result.rows.back().step_s <= newton_step) {
      result.budget_at_newton_time = budget;
      result.error_at_newton_time = result.rows.back().state_error;
    }
  }
  std::fprintf(stderr, "%d tets: matched tolerance %g\n", result.tets, settings.matched_tolerance);
  result.rows.push_back(summarize("newton", 0, threads, settings.matched_tolerance,
                                  newton_run(scene, settings.steps, settings.matched_tolerance), reference,
                                  rest));
  DescentOptions matched;
  matched.relative_tolerance = settings.matched_tolerance;
  matched.max_iterations = settings.matched_budget;
  result.rows.push_back(summarize("descent", 0, threads, settings.matched_tolerance,
                                  descent_run(scene, settings.steps, matched), reference, rest));
  const int scaling_budget = settings.budgets[settings.budgets.size() / 2];
  for (int t : settings.threads) {
    std::fprintf(stderr, "%d tets: descent, budget %d, %d threads\n", result.tets, scaling_budget, t);
    omp_set_num_threads(t);
    DescentOptions o;
    o.relative_tolerance = 1e-14;
    o.max_iterations = scaling_budget;
    result.rows.push_back(
        summarize("descent", scaling_budget, t, 0.0, descent_run(scene, settings.steps, o), reference, rest));
    result.rows.back().scaling = true;
    omp_set_num_threads(threads);
  }
  result.pass = time_pass(scene);
  return result;
}

// The published table (Wang & Yang 2016, full space, per time step) and tailor's device rows.
struct TableModel {
  const char* name;
  int vertices, tets;
  double paper_cpu_s, paper_gpu_s;
};
constexpr TableModel kTable[] = {{"Dragon", 16000, 58000, 1.35, 0.0328},
                                 {"Armadillo", 15000, 55000, 1.28, 0.0314},
                                 {"Box", 14000, 72000, 1.47, 0.0376},
                                 {"Double helix", 48000, 158000, 3.86, 0.0654},
                                 {"Double helix", 96000, 316000, 7.78, 0.122}};

struct DeviceRow {
  std::string model, device;
  int vertices = 0, tets = 0, budget = 0;
  double step_s = 0.0, iterations = 0.0, relative_residual = 0.0, state_error = 0.0, newton_step_s = 0.0;
  double paper_cpu_s = 0.0, paper_gpu_s = 0.0;
};

std::vector<DeviceRow> run_device_table(const Settings& settings) {
  std::vector<DeviceRow> rows;
  for (const TableModel& t : kTable) {
    const auto [a, b, c] = box_cells(std::max(8, static_cast<int>(settings.table_scale * t.vertices)),
                                     std::max(6, static_cast<int>(settings.table_scale * t.tets)));
    Scene scene = make_box_scene(a, b, c);
    const int vertices = scene.bar.mesh.num_vertices(), tets = scene.bar.mesh.num_elements();
    std::fprintf(stderr, "%s: %d x %d x %d cells, %d vertices, %d tets: Newton reference\n", t.name, a, b, c, vertices,
                 tets);
    const Trajectory reference = newton_run(scene, settings.steps, 1e-10);
    const double newton_step = median(std::vector<double>(reference.step_s));
    auto add = [&](DescentDevice device, int budget) {
      DescentOptions o;
      o.relative_tolerance = 1e-14;  // out of reach: the budget decides
      o.max_iterations = budget;
      o.preconditioner = DescentPreconditioner::vertex_blocks;
      o.device = device;
      const Row r = summarize("descent", budget, omp_get_max_threads(), 0.0, descent_run(scene, settings.steps, o),
                              reference, scene.bar.rest);
      rows.push_back({t.name, device == DescentDevice::gpu ? "gpu" : "cpu", vertices, tets, budget, r.step_s,
                      r.iterations, r.relative_residual, r.state_error, newton_step, t.paper_cpu_s, t.paper_gpu_s});
    };
    for (const int budget : settings.device_budgets) {
      std::fprintf(stderr, "%s: device, budget %d\n", t.name, budget);
      add(settings.table_on_cpu ? DescentDevice::cpu : DescentDevice::gpu, budget);
    }
    const int middle = settings.device_budgets[settings.device_budgets.size() / 2];
    std::fprintf(stderr, "%s: the same rule on the CPU, budget %d\n", t.name, middle);
    add(DescentDevice::cpu, middle);
  }
  return rows;
}

void print_device_table(const std::vector<DeviceRow>& rows) {
  std::printf("%-13s %7s %7s %-4s %6s %9s %8s %10s %10s %10s %10s %10s\n", "model", "verts", "tets", "on", "budget",
              "step/ms", "iter.", "residual", "state err", "Newton/s", "paper CPU", "paper GPU");
  for (const DeviceRow& r : rows)
    std::printf("%-13s %7d %7d %-4s %6d %9.2f %8.1f %10.2e %10.2e %10.3f %9.2fs %8.1fms\n", r.model.c_str(), r.vertices,
                r.tets, r.device.c_str(), r.budget, 1e3 * r.step_s, r.iterations, r.relative_residual, r.state_error,
                r.newton_step_s, r.paper_cpu_s, 1e3 * r.paper_gpu_s);
  std::printf(
      "(generated bars with the table's vertex/element counts; descent with the vertex-block rule and a fixed\n"
      " iteration budget per step; step/ms: median wall time per step; state err: max over steps of\n"
      " ||x - x_newton||_inf / max displacement; Newton/s: tailor's Newton per step (CHOLMOD); paper: Wang & Yang 2016)\n\n");
}

void print_tables(const std::vector<MeshResult>& meshes, double bandwidth) {
  std::printf("%7s %7s %-8s %6s %7s %9s %9s %9s %8s %10s %10s %10s\n", "tets", "dofs", "solver", "budget",
              "threads", "tolerance", "step/s", "cpu/s", "iter.", "residual", "state err", "drift");
  for (const MeshResult& m : meshes)
    for (const Row& r : m.rows)
      std::printf("%7d %7d %-8s %6d %7d %9.0e %9.3f %9.3f %8.1f %10.2e %10.2e %10.2e\n", m.tets, m.dofs,
                  r.solver.c_str(), r.budget, r.threads, r.tolerance, r.step_s, r.step_cpu_s, r.iterations,
                  r.relative_residual, r.state_error, r.energy_drift);
  std::printf(
      "(step/s: median wall time per step; cpu/s: median process CPU time per step; iter.: mean iterations per step; residual: median reached ||g|| over\n"
      " Newton's scale; state err: max over steps of ||x - x_newton||_inf / max displacement; drift: energy at\n"
      " the last step minus Newton's, over Newton's energy change; budget 0 = to the tolerance)\n\n");
  std::printf("%7s %12s %10s %12s %12s %12s %22s %14s\n", "tets", "bytes/elem", "pass/ms", "pass cpu/ms", "pass GB/s",
              "triad GB/s", "error at Newton's time", "vb pass cpu/ms");
  for (const MeshResult& m : meshes)
    std::printf("%7d %12.0f %10.2f %12.2f %12.2f %12.2f %13.2e (%d it.) %14.2f\n", m.tets, m.pass.bytes_per_element,
                1e3 * m.pass.seconds, 1e3 * m.pass.cpu_seconds, 1e-9 * m.pass.bandwidth, 1e-9 * bandwidth,
                m.error_at_newton_time, m.budget_at_newton_time, 1e3 * m.pass.vertex_block_cpu_seconds);
  std::printf(
      "(a pass: energy, gradient and block-Jacobi inverse at one state; bytes/elem: the arrays it streams\n"
      " (BlockJacobiPass::bytes_per_pass) per tet; pass GB/s: those bytes over its wall time; triad: a = b + s c\n"
      " over 128 MB arrays with the same threads; vb pass: the same pass with the vertex-block rule, the device's)\n");
}

void write_plot(const std::string& path, const std::vector<MeshResult>& meshes) {
  const Rgb colours[] = {{31, 119, 180}, {214, 39, 40}, {44, 160, 44}, {148, 103, 189}};
  LinePlot plot;
  plot.title = "descent vs Newton: state error against time per step";
  plot.x_label = "log10(median process CPU time per step / s)";
  plot.y_label = "state error (relative to the largest displacement)";
  plot.log_y = true;
  int c = 0;
  for (const MeshResult& m : meshes) {
    LineSeries descent{std::to_string(m.tets) + " tets, descent budgets", colours[c++ % 4], {}, {}};
    double newton_step = 0, lo = 1e300, hi = 0;
    for (const Row& r : m.rows) {
      if (r.solver == "newton" && r.tolerance == 1e-10) newton_step = r.step_cpu_s;
      if (r.solver != "descent" || r.budget == 0 || r.scaling) continue;
      descent.x.push_back(std::log10(r.step_cpu_s));
      descent.y.push_back(std::max(r.state_error, 1e-12));
      lo = std::min(lo, descent.y.back()), hi = std::max(hi, descent.y.back());
    }
    plot.series.push_back(descent);
    // Newton's CPU time per step (the reference) as a vertical line.
    plot.series.push_back({std::to_string(m.tets) + " tets, Newton", colours[c++ % 4],
                           {std::log10(newton_step), std::log10(newton_step)}, {lo, hi}});
  }
  write_line_plot_png(path, plot);
}

bench::Json to_json(const MeshResult& m, double bandwidth) {
  bench::Json rows = bench::Json::array();
  for (const Row& r : m.rows)
    rows.push_back({{"solver", r.solver},
                    {"budget", r.budget},
                    {"threads", r.threads},
                    {"tolerance", r.tolerance},
                    {"median_step_s", r.step_s},
                    {"median_step_cpu_s", r.step_cpu_s},
                    {"iterations_per_step", r.iterations},
                    {"median_relative_residual", r.relative_residual},
                    {"state_error", r.state_error},
                    {"energy_drift", r.energy_drift}});
  return {{"tets", m.tets},
          {"dofs", m.dofs},
          {"rows", rows},
          {"pass_bytes_per_element", m.pass.bytes_per_element},
          {"pass_s", m.pass.seconds},
          {"pass_cpu_s", m.pass.cpu_seconds},
          {"pass_bandwidth_bytes_per_s", m.pass.bandwidth},
          {"vertex_block_pass_s", m.pass.vertex_block_seconds},
          {"vertex_block_pass_cpu_s", m.pass.vertex_block_cpu_seconds},
          {"triad_bandwidth_bytes_per_s", bandwidth},
          {"budget_at_newton_time", m.budget_at_newton_time},
          {"error_at_newton_time", m.error_at_newton_time}};
}

}  // namespace

int run(int argc, char** argv) {
  Settings settings;
  std::string out = "bench_descent.json", plot = "bench_descent.png";
  bench::Cli cli("descent_bench", "Speed against error of the descent solver against Newton on implicit steps.");
  cli.tets(settings.tets, 24);
  cli.steps(settings.steps);
  cli.integers("--budgets", settings.budgets, "descent iteration budgets per step", 1);
  cli.integers("--threads", settings.threads, "OpenMP thread counts of the scaling runs", 1);
  cli.number("--matched-tolerance", settings.matched_tolerance, "relative tolerance of the matched runs", 0.0);
  cli.out(out);
  cli.text("--plot", plot, "PNG of state error against time per step", "FILE");
  cli.flag("--device-table", settings.device_table,
           "only the GPU rows at the published table's sizes (skipped without a CUDA device)");
  cli.integers("--device-budgets", settings.device_budgets, "descent iteration budgets per step of the GPU rows", 1);
  cli.flag("--table-on-cpu", settings.table_on_cpu, "with --device-table: the rule on the CPU in place of the device");
  cli.number("--table-scale", settings.table_scale, "with --device-table: the table's counts times this", 0.0);
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  if (settings.device_table) {
    bench::Json json = bench::report("descent_device_step");
    json["steps"] = settings.steps;
    json["device"] = cuda_device_name();
    if (!cuda_device_usable() && !settings.table_on_cpu) {
      std::printf("descent_bench --device-table: %s; the device rows are skipped\n",
                  built_with_cuda() ? "no CUDA device is usable" : "this build has no CUDA path");
      json["skipped"] = built_with_cuda() ? "no CUDA device" : "built without CUDA";
      return bench::write_report(out, json, "descent_bench") ? 0 : 1;
    }
    std::printf("tailor %s: descent on %s, implicit Euler, h = 0.01, Neo-Hookean, %d steps, %d CPU threads\n",
                version_string, settings.table_on_cpu ? "the CPU" : cuda_device_name().c_str(), settings.steps,
                omp_get_max_threads());
    const std::vector<DeviceRow> rows = run_device_table(settings);
    print_device_table(rows);
    bench::Json results = bench::Json::array();
    for (const DeviceRow& r : rows)
      results.push_back({{"model", r.model},
                         {"device", r.device},
                         {"vertices", r.vertices},
                         {"tets", r.tets},
                         {"budget", r.budget},
                         {"median_step_s", r.step_s},
                         {"iterations_per_step", r.iterations},
                         {"median_relative_residual", r.relative_residual},
                         {"state_error", r.state_error},
                         {"newton_median_step_s", r.newton_step_s},
                         {"paper_cpu_step_s", r.paper_cpu_s},
                         {"paper_gpu_step_s", r.paper_gpu_s}});
    json["results"] = results;
    return bench::write_report(out, json, "descent_bench") ? 0 : 1;
  }
  std::printf("tailor %s: cantilever under gravity, implicit Euler, h = 0.01, Neo-Hookean, %d steps, %d threads\n",
              version_string, settings.steps, omp_get_max_threads());
  const double bandwidth = triad_bandwidth();
  std::vector<MeshResult> meshes;
  for (int target : settings.tets) meshes.push_back(run_mesh(target, settings));
  print_tables(meshes, bandwidth);
  write_plot(plot, meshes);
  std::printf("wrote %s\n", plot.c_str());
  bench::Json json = bench::report("descent_step");
  json["steps"] = settings.steps;
  bench::Json results = bench::Json::array();
  for (const MeshResult& m : meshes) results.push_back(to_json(m, bandwidth));
  json["results"] = results;
  return bench::write_report(out, json, "descent_bench") ? 0 : 1;
}

}  // namespace tailor::bench::descent_bench
