// Speed against error of reduced StVK dynamics (Barbic & James 2005) compared with full-space
// dynamics of the same model, time step and scheme (Newmark average acceleration).
//
// Scene: a 4 x 1 x 1 StVK cantilever (E = 5e6, nu = 0.3, density 1000, consistent mass),
// clamped at x = 0, at rest when gravity (9.81, downwards) is switched on at t = 0: it swings
// down to about twice its static deflection (the tip falls by ~1.2, 30% of the length, near
// t = 0.7 s). Rayleigh damping alpha = 0, beta = 1e-3 s (K at rest) in both. Both runs use
// Newmark with h = 0.02 s for 1 s (50 steps) by default (the full-space run on 58k tets is
// the costly part). Meshes: bench::cantilever_cells(--tets), 3,000 and 57,798 tets by default.
//
// Reduced settings (same scheme and h): r = 10, 20, 40 linear modes (--modes), and m = 5, 10
// linear modes with their modal derivatives (--derivative-modes; m + m (m + 1) / 2 vectors,
// mass-orthonormalized: r = 20, 65). Gravity enters as the constant reduced force Phi^T M g.
// Linear modal dynamics of the same r linear modes, without and with modal warping (Choi & Ko
// 2005; forward/meshless/modal_warping.hpp, per-vertex rotations from the tets' curl): each mode
// a Rayleigh-damped oscillator stepped exactly over h, gravity M g rotated into the vertices'
// local frames for the warped rows (Phi^T M g unrotated for the linear ones), the displacement
// of every vertex warped each step. Reported per setting:
//  - median time per step (wall and process CPU; steps/s = 1 / wall median);
//  - precomputation: modal analysis (once per mesh for the largest count, shared), modal
//    derivatives, orthonormalization, StVK coefficients;
//  - trajectory error e_traj = sqrt(sum_n |u_r(t_n) - u_f(t_n)|^2_M / sum_n |u_f(t_n)|^2_M)
//    over all steps n = 1..N and all vertices (M the consistent mass matrix, u = x - X);
//  - tip error: the tip point is the mean displacement of the vertices of the end face x = 4;
//    peak tip error = max_n |tip_r(t_n) - tip_f(t_n)| (length units), also relative to the
//    peak tip displacement of the full run.
// Writes JSON (--out, default bench_reduction_error.json), prints a table and writes PNG plots
// (--plot, default bench_reduction_error.png: error against time per step; and *_tip.png: tip fall
// over time on the last mesh, full and reduced).
//
// usage: reduction_error_bench [--quick] [--tets 3000,58000] [--modes 10,20,40] [--derivative-modes 5,10]
//                              [--duration 1] [--time-step 0.02] [--out FILE] [--plot FILE]
// --quick: the 3,000-tet mesh only, 0.3 s of motion.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "bench_cli.hpp"
#include "cantilever.hpp"
#include "forward/dynamics/setup.hpp"
#include "forward/dynamics/time_integrator.hpp"
#include "forward/fem/mass.hpp"
#include "forward/meshless/modal_warping.hpp"
#include "forward/reduction/mass_orthonormal_basis.hpp"
#include "forward/reduction/modal_analysis.hpp"
#include "forward/reduction/modal_derivatives.hpp"
#include "forward/reduction/reduced_dynamics.hpp"
#include "forward/reduction/reduced_stvk.hpp"
#include "problems/plot/line_plot.hpp"
#include "tailor_version.hpp"

namespace tailor::bench::reduction_error_bench {

using namespace tailor;
using bench::Clock;
using bench::cpu_seconds;
using bench::median;
using bench::seconds_since;

namespace {

constexpr double kLength = 4.0, kYoung = 5e6, kPoisson = 0.3, kDensity = 1000.0, kGravity = 9.81;
constexpr double kBeta = 1e-3;

struct Setting {
  std::string basis;  // "modes" or "modes+derivatives"
  int linear_modes = 0;
};

struct Row {
  int tets = 0;
  std::string basis;
  int linear_modes = 0, r = 0;
  double step_s = 0, step_cpu_s = 0, steps_per_s = 0, newton_per_step = 0;
  double derivatives_s = 0, orthonormalize_s = 0, coefficients_s = 0, precompute_s = 0;
  double trajectory_error = 0, peak_tip_error = 0, peak_tip_error_relative = 0;
  std::vector<double> tip_fall;  // per state
};

struct MeshResult {
  int tets = 0, vertices = 0, free_dofs = 0, steps = 0, modal_count = 0;
  double modal_s = 0, full_step_s = 0, full_step_cpu_s = 0, full_newton_per_step = 0, full_total_s = 0;
  double full_assembly_s = 0, full_factorization_s = 0, full_line_search_s = 0;  // per step, wall
  double peak_tip = 0;
  std::vector<double> tip_fall;
  std::vector<Row> rows;
};

// Mean displacement of the tip vertices (3-vector) from a full displacement u.
Eigen::Vector3d tip_point(const Vector& u, const std::vector<int>& tip) {
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  for (int v : tip) t += u.segment<3>(3 * v);
  return t / static_cast<double>(tip.size());
}

// Full-space displacements u = x - X per state (num_dofs x (steps + 1)), the tip point per
// state and sum_{n >= 1} |u_n|^2_M.
struct FullSpaceReference {
  Matrix u;
  std::vector<Eigen::Vector3d> tip;
  double norm2 = 0.0;
  double tip_peak() const {
    double peak = 0.0;
    for (const Eigen::Vector3d& t : tip) peak = std::max(peak, t.norm());
    return peak;
  }
};

// The full-space reference: Newmark steps of the dynamic model from rest; fills the full-space
// fields of `result` (timings, tip fall) and returns the displacement of every state.
FullSpaceReference simulate_full_space(bench::Cantilever& full, const Vector& p_full,
                                       const SparseMatrix& mass, const std::vector<int>& tip, double h,
                                       int steps, MeshResult& result) {
  TimeIntegratorOptions options;
  options.scheme = TimeScheme::newmark;
  options.time_step = h;
  TimeIntegrator integrator(*full.model, options);
  DynamicState state = integrator.initial_state(full.rest, Vector::Zero(full.rest.size()), p_full);
  FullSpaceReference reference;
  Matrix& u_full = reference.u;
  u_full.resize(full.rest.size(), steps + 1);
  u_full.col(0).setZero();
  std::vector<double> wall, cpu;
  int iterations = 0;
  const auto t_full = Clock::now();
  for (int s = 0; s < steps; ++s) {
    const auto t0 = Clock::now();
    const double c0 = cpu_seconds();
    const NewtonResult r = integrator.step(state, p_full);
    wall.push_back(seconds_since(t0));
    cpu.push_back(cpu_seconds() - c0);
    if (!r.converged())
      throw std::runtime_error("full-space step " + std::to_string(s + 1) + " failed: " + r.message);
    iterations += r.iterations;
    for (const NewtonIteration& it : r.history) {
      result.full_assembly_s += it.assembly_seconds / steps;
      result.full_factorization_s += it.factorization_seconds / steps;
      result.full_line_search_s += it.line_search_seconds / steps;
    }
    u_full.col(s + 1) = state.x - full.rest;
    if ((s + 1) % 10 == 0 || s + 1 == steps) {
      std::fprintf(stderr, "  full space: step %d/%d, %.3f s, %d Newton iterations, tip z %.3f\n", s + 1,
                   steps, wall.back(), r.iterations, tip_point(u_full.col(s + 1), tip).z());
    }
  }
  result.full_total_s = seconds_since(t_full);
  result.full_step_s = median(wall);
  result.full_step_cpu_s = median(cpu);
  result.full_newton_per_step = static_cast<double>(iterations) / steps;
  reference.tip.resize(steps + 1);
  for (int n = 0; n <= steps; ++n) {
    reference.tip[n] = tip_point(u_full.col(n), tip);
    result.tip_fall.push_back(-reference.tip[n].z());
    result.peak_tip = std::max(result.peak_tip, reference.tip[n].norm());
    if (n > 0) reference.norm2 += u_full.col(n).dot(mass * u_full.col(n));
  }
  std::printf(
      "  full space: median step %.4f s (CPU %.4f s), %.2f Newton/step (per step: assembly %.3f s, "
      "factorization %.3f s, line search %.3f s), %.1f s in all; peak tip displacement %.3f\n",
      result.full_step_s, result.full_step_cpu_s, result.full_newton_per_step, result.full_assembly_s,
      result.full_factorization_s, result.full_line_search_s, result.full_total_s, result.peak_tip);
  std::fflush(stdout);

  return reference;
}

// One reduced setting: basis, StVK coefficients, Newmark steps from rest under the projected
// gravity force, and its errors against the full-space reference.
Row run_reduced(const Setting& setting, const ModalAnalysis& modes, const bench::Cantilever& elastic,
                const Vector& p, const SparseMatrix& mass, const Vector& gravity_force, double h, int steps,
                const FullSpaceReference& reference, const std::vector<int>& tip) {
  Row row;
  row.tets = elastic.mesh.num_elements();
  row.basis = setting.basis;
  row.linear_modes = setting.linear_modes;
  Matrix basis;
  if (setting.basis == "modes") {
    basis = modes.modes.leftCols(setting.linear_modes);
  } else {
    const int k = setting.linear_modes;
    auto t = Clock::now();
    const Matrix psi = modal_derivatives(*elastic.model, elastic.rest, p, modes.modes.leftCols(k));
    row.derivatives_s = seconds_since(t);
    Matrix all(modes.modes.rows(), k + psi.cols());
    all << modes.modes.leftCols(k), psi;
    t = Clock::now();
    basis = mass_orthonormal_basis(all, mass);
    row.orthonormalize_s = seconds_since(t);
  }
  row.r = static_cast<int>(basis.cols());
  const ReducedStvk reduced(*elastic.model, p, basis);
  row.coefficients_s = reduced.precomputation_seconds();
  row.precompute_s = row.derivatives_s + row.orthonormalize_s + row.coefficients_s;

  ReducedDynamicsOptions reduced_options;
  reduced_options.integrator = ReducedIntegrator::newmark;
  reduced_options.time_step = h;
  reduced_options.rayleigh_mass = 0.0;
  reduced_options.rayleigh_stiffness = kBeta;
  reduced_options.newton_tolerance = 1e-10;
  const ReducedDynamics dynamics(reduced, reduced_options, Matrix(), basis.transpose() * gravity_force);
  ReducedTrajectory trajectory;
  trajectory.states.push_back(dynamics.initial_state(Vector::Zero(row.r), Vector::Zero(row.r)));
  std::vector<double> step_wall, step_cpu;
  for (int s = 0; s < steps; ++s) {
    ReducedState next;
    int newton = 0;
    std::string message;
    const auto t0 = Clock::now();
    const double c0 = cpu_seconds();
    const bool ok = dynamics.step(trajectory.states.back(), next, newton, message);
    step_wall.push_back(seconds_since(t0));
    step_cpu.push_back(cpu_seconds() - c0);
    if (!ok)
      throw std::runtime_error(row.basis + " r = " + std::to_string(row.r) + ": step " +
                               std::to_string(s + 1) + " failed: " + message);
    trajectory.newton_iterations += newton;
    trajectory.states.push_back(std::move(next));
  }
  row.step_s = median(step_wall);
  row.step_cpu_s = median(step_cpu);
  row.steps_per_s = 1.0 / row.step_s;
  row.newton_per_step = static_cast<double>(trajectory.newton_iterations) / steps;

  double error2 = 0.0;
  for (int n = 0; n <= steps; ++n) {
    const Vector u = basis * trajectory.states[n].q;
    const Eigen::Vector3d tip_r = tip_point(u, tip);
    row.tip_fall.push_back(-tip_r.z());
    row.peak_tip_error = std::max(row.peak_tip_error, (tip_r - reference.tip[n]).norm());
    if (n > 0) {
      const Vector e = u - reference.u.col(n);
      error2 += e.dot(mass * e);
    }
  }
  row.trajectory_error = std::sqrt(error2 / reference.norm2);
  row.peak_tip_error_relative = row.peak_tip_error / reference.tip_peak();
  std::printf(
      "  %-17s m = %2d, r = %2d: %8.5f s/step (%.0f steps/s), %.2f Newton/step, precompute %.2f s, "
      "trajectory error %.3e, peak tip error %.4f (%.2f%%)\n",
      row.basis.c_str(), row.linear_modes, row.r, row.step_s, row.steps_per_s, row.newton_per_step,
      row.precompute_s, row.trajectory_error, row.peak_tip_error, 100 * row.peak_tip_error_relative);
  std::fflush(stdout);
  return row;
}

// Linear modal dynamics of the first r modes, warped or not, against the reference. A step is
// the modal force (rotated gravity when warped), the exact damped-oscillator update and the
// displacement of every vertex.
Row run_modal(int r, bool warp, const ModalAnalysis& modes, const bench::Cantilever& elastic, const SparseMatrix& mass,
              const Vector& gravity_force, double h, int steps, const FullSpaceReference& reference,
              const std::vector<int>& tip) {
  Row row;
  row.tets = elastic.mesh.num_elements();
  row.basis = warp ? "warped modal" : "linear modal";
  row.linear_modes = r;
  row.r = r;
  auto t = Clock::now();
  WarpedModalSimulator simulator(fem_modal_warping_operators(elastic.mesh, modes.modes.leftCols(r)),
                                 modes.eigenvalues.head(r), ModalRayleighDamping{0.0, kBeta}, h);
  row.coefficients_s = seconds_since(t);
  row.precompute_s = row.coefficients_s;
  const Vector linear_force = modes.modes.leftCols(r).transpose() * gravity_force;
  std::vector<double> step_wall, step_cpu;
  double error2 = 0.0;
  Eigen::VectorXd u = Eigen::VectorXd::Zero(gravity_force.size());
  row.tip_fall.push_back(0.0);
  for (int s = 0; s < steps; ++s) {
    const auto t0 = Clock::now();
    const double c0 = cpu_seconds();
    simulator.step(warp ? simulator.modal_force(gravity_force) : linear_force);
    simulator.displacements(u, warp);
    step_wall.push_back(seconds_since(t0));
    step_cpu.push_back(cpu_seconds() - c0);
    const Eigen::Vector3d tip_r = tip_point(u, tip);
    row.tip_fall.push_back(-tip_r.z());
    row.peak_tip_error = std::max(row.peak_tip_error, (tip_r - reference.tip[s + 1]).norm());
    const Vector e = u - reference.u.col(s + 1);
    error2 += e.dot(mass * e);
  }
  row.step_s = median(step_wall);
  row.step_cpu_s = median(step_cpu);
  row.steps_per_s = 1.0 / row.step_s;
  row.trajectory_error = std::sqrt(error2 / reference.norm2);
  row.peak_tip_error_relative = row.peak_tip_error / reference.tip_peak();
  std::printf(
      "  %-17s m = %2d, r = %2d: %8.5f s/step (%.0f steps/s), operators %.2f s, trajectory error %.3e, "
      "peak tip error %.4f (%.2f%%)\n",
      row.basis.c_str(), row.linear_modes, row.r, row.step_s, row.steps_per_s, row.precompute_s,
      row.trajectory_error, row.peak_tip_error, 100 * row.peak_tip_error_relative);
  std::fflush(stdout);
  return row;
}

MeshResult run_mesh(int target_tets, double h, int steps, const std::vector<int>& mode_counts,
                    const std::vector<int>& derivative_mode_counts) {
  MeshResult result;
  const bench::CantileverCells cells = bench::cantilever_cells(target_tets, kLength);
  // Full-space model: elastic + inertia + gravity + Rayleigh damping.
  DynamicTerms terms;
  bench::Cantilever full =
      bench::make_cantilever(kLength, cells, MaterialKind::stvk, [&](Model& model, const Mesh& mesh) {
        terms = add_dynamics_terms(
            model, mesh, DynamicsSetup{MassLumping::consistent, Eigen::Vector3d(0, 0, -kGravity), true});
      });
  const int m = full.mesh.num_elements();
  Vector p_full = bench::cantilever_parameters(full, kYoung, kPoisson);
  p_full.segment(terms.density_offset, m).setConstant(kDensity);
  p_full[terms.alpha_offset] = 0.0;
  p_full[terms.beta_offset] = kBeta;
  // Elastic-only model of the same bar for modal analysis and the reduced StVK.
  const bench::Cantilever elastic = bench::make_cantilever(kLength, cells, MaterialKind::stvk);
  const Vector p = bench::cantilever_parameters(elastic, kYoung, kPoisson);
  const SparseMatrix mass =
      mass_matrix(elastic.mesh, Eigen::VectorXd::Constant(m, kDensity), MassLumping::consistent);
  const std::vector<int>& tip = elastic.tip_vertices;
  result.tets = m;
  result.vertices = elastic.mesh.num_vertices();
  result.free_dofs = elastic.model->elimination().num_free();
  result.steps = steps;
  std::printf("\nmesh: %d tets, %d vertices, %d free DOFs; %d Newmark steps of %g s\n", m, result.vertices,
              result.free_dofs, steps, h);
  std::fflush(stdout);

  const FullSpaceReference reference = simulate_full_space(full, p_full, mass, tip, h, steps, result);

  // Modal analysis once for the largest count.
  std::vector<Setting> settings;
  for (int k : mode_counts) settings.push_back({"modes", k});
  for (int k : derivative_mode_counts) settings.push_back({"modes+derivatives", k});
  result.modal_count = 0;
  for (const Setting& s : settings) result.modal_count = std::max(result.modal_count, s.linear_modes);
  auto t = Clock::now();
  ModalAnalysisOptions modal_options;
  modal_options.count = result.modal_count;
  const ModalAnalysis modes = modal_analysis(*elastic.model, 3, elastic.rest, p, mass, modal_options);
  result.modal_s = seconds_since(t);
  std::printf("  modal analysis (%d modes): %.2f s; first frequency %.3f Hz\n", result.modal_count,
              result.modal_s, modes.frequencies[0]);
  // Gravity as a constant reduced force: consistent nodal forces M g (gravity_forces).
  Vector g_field = Vector::Zero(elastic.rest.size());
  for (int v = 0; v < result.vertices; ++v) g_field[3 * v + 2] = -kGravity;
  const Vector gravity_force = mass * g_field;

  for (const Setting& setting : settings)
    result.rows.push_back(
        run_reduced(setting, modes, elastic, p, mass, gravity_force, h, steps, reference, tip));
  for (const bool warp : {false, true})
    for (int k : mode_counts)
      result.rows.push_back(run_modal(k, warp, modes, elastic, mass, gravity_force, h, steps, reference, tip));
  return result;
}

void write_plots(const std::string& path, const std::vector<MeshResult>& meshes, double h) {
  const Rgb colours[] = {{31, 119, 180},  {214, 39, 40},  {44, 160, 44},
                         {148, 103, 189}, {255, 127, 14}, {23, 190, 207}};
  LinePlot cost;
  cost.title = "reduced vs full-space Newmark: trajectory error vs cost";
  cost.x_label = "log10(median wall time per step / s)";
  cost.y_label = "relative trajectory error (M-norm)";
  cost.log_y = true;
  int c = 0;
  double y_min = 1e300, y_max = 0;
  for (const MeshResult& mesh : meshes)
    for (const Row& row : mesh.rows)
      y_min = std::min(y_min, row.trajectory_error), y_max = std::max(y_max, row.trajectory_error);
  for (const MeshResult& mesh : meshes) {
    for (const std::string basis : {"modes", "modes+derivatives", "linear modal", "warped modal"}) {
      LineSeries s{std::to_string(mesh.tets) + " tets, " + basis, colours[c++ % 6], {}, {}};
      for (const Row& row : mesh.rows)
        if (row.basis == basis) s.x.push_back(std::log10(row.step_s)), s.y.push_back(row.trajectory_error);
      cost.series.push_back(s);
    }
    // The full-space cost as a vertical line.
    cost.series.push_back({std::to_string(mesh.tets) + " tets, full space",
                           colours[c++ % 6],
                           {std::log10(mesh.full_step_s), std::log10(mesh.full_step_s)},
                           {y_min, y_max}});
  }
  write_line_plot_png(path, cost);

  const MeshResult& last = meshes.back();
  LinePlot tip;
  tip.title = "tip fall, " + std::to_string(last.tets) + " tets";
  tip.x_label = "time / s";
  tip.y_label = "tip fall (length units)";
  c = 0;
  const auto times = [h](std::size_t n) {
    std::vector<double> x(n);
    for (std::size_t k = 0; k < n; ++k) x[k] = h * static_cast<double>(k);
    return x;
  };
  tip.series.push_back({"full space", Rgb{0, 0, 0}, times(last.tip_fall.size()), last.tip_fall});
  for (const Row& row : last.rows)
    tip.series.push_back({row.basis + " r = " + std::to_string(row.r), colours[c++ % 6],
                          times(row.tip_fall.size()), row.tip_fall});
  const std::string stem =
      path.size() > 4 && path.substr(path.size() - 4) == ".png" ? path.substr(0, path.size() - 4) : path;
  write_line_plot_png(stem + "_tip.png", tip);
}

}  // namespace

int run(int argc, char** argv) {
  std::vector<int> tets = {3000, 58000}, mode_counts = {10, 20, 40}, derivative_mode_counts = {5, 10};
  double duration = 1.0, h = 0.02;
  bool quick = false;
  std::string out = "bench_reduction_error.json", plot = "bench_reduction_error.png";
  bench::Cli cli("reduction_error_bench", "Speed against error of reduced StVK dynamics vs full space.");
  cli.flag("--quick", quick, "the 3,000-tet mesh only, 0.3 s of motion");
  cli.tets(tets, 24);
  cli.integers("--modes", mode_counts, "linear mode counts r", 1);
  cli.integers("--derivative-modes", derivative_mode_counts, "linear mode counts m with modal derivatives",
               1);
  cli.number("--duration", duration, "simulated time [s]", 0.0);
  cli.time_step(h);
  cli.out(out);
  cli.text("--plot", plot, "PNG of error against time per step (and its _tip.png)", "FILE");
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  if (quick) {
    tets = {3000};
    duration = 0.3;
  }
  if (!(duration >= h)) return cli.usage_error("--duration must be at least one --time-step");
  const int steps = static_cast<int>(std::lround(duration / h));
  int threads = 1;
#ifdef _OPENMP
  threads = omp_get_max_threads();
#endif
  double load[3] = {0, 0, 0};
  if (std::ifstream loadavg("/proc/loadavg"); loadavg) loadavg >> load[0] >> load[1] >> load[2];
  std::printf(
      "tailor %s: StVK cantilever under sudden gravity, Newmark h = %g s, %d steps (%g s), %d OpenMP "
      "threads, %u hardware threads, load average %.2f %.2f %.2f\n",
      version_string, h, steps, steps * h, threads, std::thread::hardware_concurrency(), load[0], load[1],
      load[2]);
  std::vector<MeshResult> meshes;
  try {
    for (int target : tets) meshes.push_back(run_mesh(target, h, steps, mode_counts, derivative_mode_counts));
  } catch (const std::exception& e) {
    std::cerr << "reduction_error_bench: " << e.what() << "\n";
    return 1;
  }

  std::printf("\n%7s %-18s %3s %3s %11s %10s %9s %9s %9s %9s %9s %10s %9s %8s\n", "tets", "basis", "m", "r",
              "s/step", "steps/s", "cpu s/st", "newton", "modal s", "deriv s", "coeff s", "traj err",
              "tip err", "tip err%");
  for (const MeshResult& mesh : meshes) {
    std::printf("%7d %-18s %3s %3d %11.5f %10.2f %9.5f %9.2f %9s %9s %9s %10s %9s %8s\n", mesh.tets,
                "full space", "-", mesh.free_dofs, mesh.full_step_s, 1.0 / mesh.full_step_s,
                mesh.full_step_cpu_s, mesh.full_newton_per_step, "-", "-", "-", "0", "0", "0");
    for (const Row& row : mesh.rows)
      std::printf("%7d %-18s %3d %3d %11.5f %10.1f %9.5f %9.2f %9.2f %9.2f %9.2f %10.3e %9.4f %8.2f\n",
                  row.tets, row.basis.c_str(), row.linear_modes, row.r, row.step_s, row.steps_per_s,
                  row.step_cpu_s, row.newton_per_step, mesh.modal_s, row.derivatives_s + row.orthonormalize_s,
                  row.coefficients_s, row.trajectory_error, row.peak_tip_error,
                  100 * row.peak_tip_error_relative);
  }
  std::printf(
      "(s/step: median wall time per Newmark step, steps/s = 1 / s/step; cpu s/st: median process CPU time "
      "per "
      "step; r: basis size (free DOFs for full space); modal s: modal analysis of the largest mode count, "
      "shared by all "
      "settings of a mesh; deriv s: modal derivatives + mass-orthonormalization; coeff s: reduced StVK "
      "coefficients (for the linear and warped modal rows: the warping operators); traj err: sqrt(sum_n |u_r - u_f|^2_M / sum_n |u_f|^2_M) over all steps and vertices; "
      "tip "
      "err: max_n |tip_r - tip_f| for the mean displacement of the end-face vertices, and in %% of the peak "
      "tip "
      "displacement of the full run)\n");

  bench::Json json = bench::report("reduction_error");
  json["openmp_threads"] = threads;
  json["hardware_threads"] = std::thread::hardware_concurrency();
  json["load_average"] = {load[0], load[1], load[2]};
  json["scene"] = {{"length", kLength},      {"youngs_modulus", kYoung}, {"poisson_ratio", kPoisson},
                   {"density", kDensity},    {"gravity", kGravity},      {"rayleigh_alpha", 0},
                   {"rayleigh_beta", kBeta}, {"scheme", "newmark"},      {"time_step", h},
                   {"steps", steps}};
  json["error_definitions"] = {
      {"trajectory_error",
       "sqrt(sum_n |u_r(t_n) - u_f(t_n)|^2_M / sum_n |u_f(t_n)|^2_M), n = 1..steps, all vertices, M "
       "consistent "
       "mass"},
      {"peak_tip_error",
       "max_n |tip_r(t_n) - tip_f(t_n)|, tip = mean displacement of the vertices at x = length"}};
  bench::Json mesh_rows = bench::Json::array();
  for (const MeshResult& mesh : meshes) {
    bench::Json reduced = bench::Json::array();
    for (const Row& r : mesh.rows)
      reduced.push_back({{"basis", r.basis},
                         {"linear_modes", r.linear_modes},
                         {"r", r.r},
                         {"median_step_s", r.step_s},
                         {"median_step_cpu_s", r.step_cpu_s},
                         {"steps_per_s", r.steps_per_s},
                         {"newton_per_step", r.newton_per_step},
                         {"modal_derivatives_s", r.derivatives_s},
                         {"orthonormalization_s", r.orthonormalize_s},
                         {"stvk_coefficients_s", r.coefficients_s},
                         {"precompute_s_excluding_modal_analysis", r.precompute_s},
                         {"trajectory_error", r.trajectory_error},
                         {"peak_tip_error", r.peak_tip_error},
                         {"peak_tip_error_relative", r.peak_tip_error_relative}});
    mesh_rows.push_back({{"tets", mesh.tets},
                         {"vertices", mesh.vertices},
                         {"free_dofs", mesh.free_dofs},
                         {"modal_analysis_s", mesh.modal_s},
                         {"modal_count", mesh.modal_count},
                         {"peak_tip_displacement", mesh.peak_tip},
                         {"full_space",
                          {{"median_step_s", mesh.full_step_s},
                           {"median_step_cpu_s", mesh.full_step_cpu_s},
                           {"steps_per_s", 1.0 / mesh.full_step_s},
                           {"newton_per_step", mesh.full_newton_per_step},
                           {"assembly_s_per_step", mesh.full_assembly_s},
                           {"factorization_s_per_step", mesh.full_factorization_s},
                           {"line_search_s_per_step", mesh.full_line_search_s},
                           {"total_s", mesh.full_total_s}}},
                         {"reduced", reduced}});
  }
  json["meshes"] = mesh_rows;
  if (!bench::write_report(out, json, "reduction_error_bench")) return 1;
  try {
    write_plots(plot, meshes, h);
    std::printf("wrote %s and its _tip.png\n", plot.c_str());
  } catch (const std::exception& e) {
    std::cerr << "reduction_error_bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace tailor::bench::reduction_error_bench
