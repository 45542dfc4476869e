// Reduced StVK dynamics on a clamped cantilever: steps per second against the basis size r and
// the mesh size, for linear modes and for modes + modal derivatives, plus the precomputation
// times (modal analysis, modal derivatives, StVK polynomial coefficients). The per-step cost
// of the polynomial model is O(r^4) and must not depend on the mesh; one evaluation of the
// projected model (any material, cost proportional to the mesh) is timed for comparison.
//
// The beam is 10 x 1 x 1 (E = 1e6, nu = 0.3, rho = 1000, StVK), n tets-cells through the
// height (6 * 10 n^3 tets); it starts at rest with an initial velocity along its first mode
// whose tip speed makes the tip swing by about 20% of the length (large deformation), and runs
// `steps` steps of h = 1/200 s with each integrator. Writes JSON (--out, default
// bench_reduced_dynamics.json) and prints a table. Timings are whole runs divided by steps
// (the median of --repeats runs).
//
// usage: reduced_dynamics_bench [--cells 4,10] [--ranks 10,20,40] [--steps 1000] [--repeats 3] [--out FILE]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>
#include <thread>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "bench_cli.hpp"
#include "cantilever.hpp"
#include "forward/fem/mass.hpp"
#include "forward/reduction/mass_orthonormal_basis.hpp"
#include "forward/reduction/modal_analysis.hpp"
#include "forward/reduction/modal_derivatives.hpp"
#include "forward/reduction/projected_reduced_model.hpp"
#include "forward/reduction/reduced_dynamics.hpp"
#include "forward/reduction/reduced_stvk.hpp"
#include "tailor_version.hpp"

namespace tailor::bench::reduced_dynamics_bench {

using namespace tailor;

namespace {

using bench::Clock;
using bench::median;
double since(Clock::time_point t) { return bench::seconds_since(t); }

struct Beam {
  bench::Cantilever bar;
  Vector p;
  SparseMatrix mass;
};

Beam make_beam(int n) {
  Beam b;
  b.bar = bench::make_cantilever(10.0, {10 * n, n}, MaterialKind::stvk);
  const int m = b.bar.mesh.num_elements();
  b.p = bench::cantilever_parameters(b.bar, 1e6, 0.3);
  b.mass = mass_matrix(b.bar.mesh, Eigen::VectorXd::Constant(m, 1000.0), MassLumping::consistent);
  return b;
}

struct Row {
  int tets = 0, rank = 0, linear_modes = 0;
  std::string basis;
  double precompute_s = 0, precompute_cpu_s = 0, basis_s = 0, projected_eval_s = 0;
  double steps_per_s[4] = {}, cpu_steps_per_s[4] = {}, newton_per_step[4] = {}, tip_max[4] = {};
};

}  // namespace

int run(int argc, char** argv) {
  std::vector<int> cells = {4, 10}, ranks = {10, 20, 40};
  int steps = 1000, repeats = 3;
  std::string out = "bench_reduced_dynamics.json";
  bench::Cli cli("reduced_dynamics_bench",
                 "Reduced StVK dynamics of a cantilever: steps per second against r.");
  cli.integers("--cells", cells, "cells through the beam's height (6 * 10 n^3 tets)", 1);
  cli.integers("--ranks", ranks, "basis sizes r", 1);
  cli.steps(steps);
  cli.repeats(repeats);
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  int threads = 1;
#ifdef _OPENMP
  threads = omp_get_max_threads();
#endif
  const int max_rank = *std::max_element(ranks.begin(), ranks.end());
  std::printf(
      "tailor %s, reduced StVK cantilever dynamics, %d steps of 1/200 s, %d OpenMP threads, %u hardware "
      "threads\n",
      version_string, steps, threads, std::thread::hardware_concurrency());
  std::vector<Row> rows;
  struct MeshInfo {
    int tets, vertices;
    double modal_s, derivative_s, modal_cpu_s;
  };
  std::vector<MeshInfo> meshes;
  for (int n : cells) {
    const Beam beam = make_beam(n);
    const int tets = beam.bar.mesh.num_elements();
    std::printf("\nmesh: %d tets, %d vertices\n", tets, beam.bar.mesh.num_vertices());
    std::fflush(stdout);
    auto t = Clock::now();
    const std::clock_t modal_cpu = std::clock();
    ModalAnalysisOptions modal_options;
    modal_options.count = max_rank;
    const ModalAnalysis modes =
        modal_analysis(*beam.bar.model, 3, beam.bar.rest, beam.p, beam.mass, modal_options);
    const double modal_s = since(t),
                 modal_cpu_s = static_cast<double>(std::clock() - modal_cpu) / CLOCKS_PER_SEC;
    std::printf("  modal analysis (%d modes): %.2f s (CPU %.2f s), first frequencies %.3f %.3f Hz\n",
                max_rank, modal_s, modal_cpu_s, modes.frequencies[0], modes.frequencies[1]);
    // Modes + derivatives: the smallest m with m + m (m + 1) / 2 >= r, truncated to r after
    // orthonormalization (derivatives computed once for the largest m).
    const auto modes_for = [](int r) {
      int m = 1;
      while (m + m * (m + 1) / 2 < r) ++m;
      return m;
    };
    const int max_m = modes_for(max_rank);
    t = Clock::now();
    const Matrix psi = modal_derivatives(*beam.bar.model, beam.bar.rest, beam.p, modes.modes.leftCols(max_m));
    const double derivative_s = since(t);
    std::printf("  modal derivatives of %d modes (%d vectors): %.2f s\n", max_m, static_cast<int>(psi.cols()),
                derivative_s);
    meshes.push_back({tets, beam.bar.mesh.num_vertices(), modal_s, derivative_s, modal_cpu_s});
    for (const bool with_derivatives : {false, true}) {
      for (int r : ranks) {
        Row row;
        row.tets = tets;
        row.rank = r;
        row.basis = with_derivatives ? "modes+derivatives" : "modes";
        Matrix basis;
        t = Clock::now();
        if (with_derivatives) {
          const int m = modes_for(r);
          Matrix all(modes.modes.rows(), m + m * (m + 1) / 2);
          all << modes.modes.leftCols(m), psi.leftCols(0);
          // Psi_ij for i <= j < m: the columns of the max_m block with both indices below m.
          int c = m;
          for (int i = 0; i < m; ++i)
            for (int j = i; j < m; ++j) all.col(c++) = psi.col(modal_derivative_index(i, j, max_m));
          basis = mass_orthonormal_basis(all, beam.mass).leftCols(r);
          row.linear_modes = m;
        } else {
          basis = modes.modes.leftCols(r);
          row.linear_modes = r;
        }
        row.basis_s = since(t);
        const std::clock_t precompute_cpu = std::clock();
        const ReducedStvk reduced(*beam.bar.model, beam.p, basis);
        row.precompute_s = reduced.precomputation_seconds();
        row.precompute_cpu_s = static_cast<double>(std::clock() - precompute_cpu) / CLOCKS_PER_SEC;
        {
          const ProjectedReducedModel projected(*beam.bar.model, beam.p, beam.bar.rest, basis);
          Vector f;
          Matrix k;
          t = Clock::now();
          projected.evaluate(Vector::Constant(r, 1e-3), nullptr, &f, &k);
          row.projected_eval_s = since(t);
        }
        const Matrix tip_rows = vertex_rows(basis, beam.bar.tip_vertices, 3);
        for (int integrator = 0; integrator < 4;
             ++integrator) {  // Euler, Newmark, Newmark chord, Newmark 1 step
          ReducedDynamicsOptions options;
          options.integrator =
              integrator == 0 ? ReducedIntegrator::implicit_euler : ReducedIntegrator::newmark;
          if (integrator == 2) options.jacobian = ReducedJacobian::once_per_step;
          if (integrator == 3) options.max_newton_iterations = 1, options.accept_unconverged = true;
          options.time_step = 1.0 / 200.0;
          options.rayleigh_mass = 0.2;
          options.rayleigh_stiffness = 1e-4;
          options.newton_tolerance = 1e-8;
          const ReducedDynamics dynamics(reduced, options);
          // Initial velocity along mode 1 (basis column 0), tip speed 1.5 length units / s.
          Vector v0 = Vector::Zero(r);
          v0[0] = 1.5 / tip_rows.col(0).cwiseAbs().maxCoeff();
          std::vector<double> seconds, cpu_seconds;
          ReducedTrajectory trajectory;
          for (int k = 0; k < repeats; ++k) {
            t = Clock::now();
            const std::clock_t cpu = std::clock();
            trajectory = dynamics.simulate(Vector::Zero(r), v0, steps);
            cpu_seconds.push_back(static_cast<double>(std::clock() - cpu) / CLOCKS_PER_SEC);
            seconds.push_back(since(t));
          }
          if (!trajectory.converged) std::printf("  WARNING: %s\n", trajectory.message.c_str());
          row.steps_per_s[integrator] = steps / median(seconds);
          row.cpu_steps_per_s[integrator] = steps / median(cpu_seconds);
          row.newton_per_step[integrator] = static_cast<double>(trajectory.newton_iterations) / steps;
          row.tip_max[integrator] = vertex_displacements(trajectory, tip_rows).cwiseAbs().maxCoeff();
        }
        std::printf(
            "  %-18s r = %2d: precompute %7.3f s (CPU %.3f s); steps/s (CPU time): implicit Euler %.0f (%.2f "
            "Newton/step), "
            "Newmark %.0f (%.2f), Newmark chord %.0f (%.2f), Newmark 1 Newton step %.0f; tip max %.2f (1 "
            "step: %.2f); "
            "projected force+stiffness %.4f s\n",
            row.basis.c_str(), r, row.precompute_s, row.precompute_cpu_s, row.cpu_steps_per_s[0],
            row.newton_per_step[0], row.cpu_steps_per_s[1], row.newton_per_step[1], row.cpu_steps_per_s[2],
            row.newton_per_step[2], row.cpu_steps_per_s[3], row.tip_max[1], row.tip_max[3],
            row.projected_eval_s);
        std::fflush(stdout);
        rows.push_back(row);
      }
    }
  }

  std::printf("\n%8s %-18s %4s %11s %11s %11s %11s %11s %11s %9s %13s\n", "tets", "basis", "r", "precomp s",
              "Euler", "Newmark", "chord", "1-step", "1-step wall", "tip max", "projected s");
  for (const Row& row : rows)
    std::printf("%8d %-18s %4d %11.3f %11.0f %11.0f %11.0f %11.0f %11.0f %9.2f %13.4f\n", row.tets,
                row.basis.c_str(), row.rank, row.precompute_s, row.cpu_steps_per_s[0], row.cpu_steps_per_s[1],
                row.cpu_steps_per_s[2], row.cpu_steps_per_s[3], row.steps_per_s[3], row.tip_max[1],
                row.projected_eval_s);
  std::printf(
      "(steps per second of CPU time, single thread, median of %d runs of %d steps, except '1-step wall': "
      "wall "
      "clock; Euler / Newmark: full Newton to 1e-8; chord: Newmark with the Jacobian once per step; 1-step: "
      "Newmark with one Newton step per time step (Barbic & James 2005); precomp: StVK coefficients (wall, "
      "OpenMP); projected: one force + stiffness of the projected full model, cost proportional to the "
      "mesh)\n",
      repeats, steps);

  bench::Json json = bench::report("reduced_dynamics");
  json["openmp_threads"] = threads;
  json["hardware_threads"] = std::thread::hardware_concurrency();
  json["steps"] = steps;
  json["repeats"] = repeats;
  json["time_step"] = 0.005;
  bench::Json mesh_rows = bench::Json::array();
  for (const MeshInfo& mesh : meshes)
    mesh_rows.push_back({{"tets", mesh.tets},
                         {"vertices", mesh.vertices},
                         {"modal_analysis_s", mesh.modal_s},
                         {"modal_analysis_cpu_s", mesh.modal_cpu_s},
                         {"modal_derivatives_s", mesh.derivative_s}});
  json["meshes"] = mesh_rows;
  bench::Json results = bench::Json::array();
  for (const Row& r : rows)
    results.push_back({{"tets", r.tets},
                       {"basis", r.basis},
                       {"r", r.rank},
                       {"linear_modes", r.linear_modes},
                       {"basis_s", r.basis_s},
                       {"precompute_s", r.precompute_s},
                       {"precompute_cpu_s", r.precompute_cpu_s},
                       {"implicit_euler_steps_per_s", r.steps_per_s[0]},
                       {"implicit_euler_newton_per_step", r.newton_per_step[0]},
                       {"newmark_steps_per_s", r.steps_per_s[1]},
                       {"newmark_newton_per_step", r.newton_per_step[1]},
                       {"newmark_chord_steps_per_s", r.steps_per_s[2]},
                       {"newmark_chord_newton_per_step", r.newton_per_step[2]},
                       {"newmark_one_step_steps_per_s", r.steps_per_s[3]},
                       {"cpu_steps_per_s",
                        {{"implicit_euler", r.cpu_steps_per_s[0]},
                         {"newmark", r.cpu_steps_per_s[1]},
                         {"newmark_chord", r.cpu_steps_per_s[2]},
                         {"newmark_one_step", r.cpu_steps_per_s[3]}}},
                       {"tip_max_displacement_one_step", r.tip_max[3]},
                       {"tip_max_displacement", r.tip_max[1]},
                       {"projected_force_stiffness_s", r.projected_eval_s}});
  json["results"] = results;
  return bench::write_report(out, json, "reduced_dynamics_bench") ? 0 : 1;
}

}  // namespace tailor::bench::reduced_dynamics_bench
