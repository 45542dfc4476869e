// Material design with a handle in reduced displacements and reduced materials (Xu, Li, Chen,
// Barbic 2015; problems/reduced_design.hpp) against the full-space design (the existing path:
// granularity "modes" with the log map, every iteration a full-space Newton solve and adjoint;
// ceres_lbfgs, as nlopt_lbfgs stops at the start of this scene with NLOPT_FAILURE).
//
// Scene: a 10 x 1 x 1 StVK cantilever, 10 c x c x c cells (60 c^3 tets, --cells), clamped at
// x = 0; a handle on the tip face pushed down by a total force of 100 must reach a mean
// displacement ubar: the full-space response of the known graded design E = E0 (1 - 0.6 + 0.2
// y_2) (so a design exists). For each cell count and each (displacement modes, material modes)
// in --displacement-modes x --material-modes it reports the precomputation (modes, responses,
// derivatives, coefficients, refinements), the median milliseconds per optimizer iteration, the
// iterations and passes, and the full-space handle error |mean u - ubar| / |ubar| of the final
// design (its full-space solve); then the full-space design with --material-modes' largest m,
// with iteration caps 25, 50, ... up to --full-iterations until its full-space handle error is at
// most the reduced runs' worst,
// with its median seconds per iteration. JSON (--out, default bench_reduced_design.json) and a
// table; ratios are per iteration, in the same run.
//
// usage: reduced_design_bench [--quick] [--cells 2,4] [--displacement-modes 4,8]
//          [--material-modes 4,8] [--max-iterations 100] [--full-iterations 50] [--out FILE] [--no-full]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "problems/inverse_commands.hpp"
#include "problems/reduced_design.hpp"

using namespace tailor;

namespace {

using Clock = std::chrono::steady_clock;

double median_of(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string num(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

// The scene; `design` is the inverse.design object.
std::string scene_text(int c, const std::string& design, const std::string& target, int max_iterations,
                       double beta = 1e4, const std::string& backend = "nlopt_lbfgs") {
  return R"({"name": "reduced_design_bench",
  "mesh": {"box": {"min": [0, 0, 0], "max": [10, 1, 1], "cells": [)" +
         std::to_string(10 * c) + ", " + std::to_string(c) + ", " + std::to_string(c) + R"(]}},
  "materials": [{"elements": "all", "model": "stvk", "youngs_modulus": 1e6, "poisson_ratio": 0.3, "density": 1000}],
  "dirichlet": [{"vertices": {"plane": {"axis": "x", "value": 0}}}],
  "inverse": {"design": )" +
         design + R"(,
    "objective": [{"type": "handles", "alpha": 1e-4, "beta": )" +
         num(beta) + R"(, "handles": [
      {"vertices": {"plane": {"axis": "x", "value": 10}}, "force": [0, 0, -100], "displacement": )" +
         target + R"(}]}],
    "optimizer": {"backend": ")" +
         backend + R"(", "max_iterations": )" + std::to_string(max_iterations) +
         R"(, "gradient_tolerance": 1e-8, "objective_tolerance": 1e-12}}})";
}

std::string reduced_design_key(int k, int m) {
  return R"({"parameter": "youngs_modulus", "granularity": "modes", "modes": )" + std::to_string(m) +
         R"(, "map": "identity", "reduction": {"displacement_modes": )" + std::to_string(k) +
         R"(, "smoothness": 1e-4}})";
}

Scene parse(const std::string& text) { return parse_scene(text, "reduced_design_bench.json", "."); }

struct Row {
  int cells = 0, tets = 0, k = 0, m = 0, r = 0, passes = 0, iterations = 0;
  double precompute = 0, coefficients = 0, refinement = 0, median_ms = 0, optimize = 0;
  double reduced_error = 0, full_error = 0, full_solve = 0;
  std::string status;
};

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> cells{2, 4}, ks{4, 8}, ms{4, 8};
  int max_iterations = 100, full_iterations = 50;
  bool quick = false, no_full = false;
  std::string out = "bench_reduced_design.json";
  bench::Cli cli("reduced_design_bench", "reduced vs full-space material design with a handle");
  cli.integers("--cells", cells, "cells through the beam's height (60 c^3 tets)", 1);
  cli.integers("--displacement-modes", ks, "linear vibration modes in the reduced basis", 1);
  cli.integers("--material-modes", ms, "Laplacian material modes", 2);
  cli.integer("--max-iterations", max_iterations, "optimizer iterations per pass (and full design)", 1);
  cli.integer("--full-iterations", full_iterations,
              "largest iteration cap of the full-space design (25, 50, ...)", 1);
  cli.flag("--quick", quick, "cells 2, one grid point (4 x 4)");
  cli.flag("--no-full", no_full, "skip the full-space design");
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  if (quick) cells = {2}, ks = {4}, ms = {4};

  bench::Json json = bench::report("reduced_design");
  bench::Json rows_json = bench::Json::array(), full_json = bench::Json::array();
  std::vector<Row> rows;
  const int m_full = *std::max_element(ms.begin(), ms.end());
  for (int c : cells) {
    // The target: the full-space response of the graded design w* (first two modes).
    std::string target;
    double target_norm = 1.0;
    {
      const ReducedDesign probe =
          build_reduced_design(parse(scene_text(c, reduced_design_key(2, 2), "[0, 0, -1]", 1)));
      Vector w = Vector::Zero(probe.num_design());
      w[0] = -0.6;
      w[1] = 0.2;
      const FullSpaceCheck truth = full_space_check(probe, w);
      if (!truth.converged) {
        std::cerr << "the target's full-space solve failed: " << truth.message << "\n";
        return 1;
      }
      Vector mean = Vector::Zero(3);
      for (int v : probe.handles[0].vertices) mean += truth.displacement.segment(3 * v, 3);
      mean /= static_cast<double>(probe.handles[0].vertices.size());
      target = "[" + num(mean[0]) + ", " + num(mean[1]) + ", " + num(mean[2]) + "]";
      target_norm = mean.norm();
      std::printf("cells %d: %d tets, target mean tip displacement %s\n", c, probe.setup.mesh.num_elements(),
                  target.c_str());
    }
    double worst_full = 0.0;
    for (int k : ks)
      for (int m : ms) {
        ReducedDesign design =
            build_reduced_design(parse(scene_text(c, reduced_design_key(k, m), target, max_iterations)));
        const ReducedDesignRun run = run_reduced_design(design, "");
        Row row;
        row.cells = c;
        row.tets = design.setup.mesh.num_elements();
        row.k = k;
        row.m = m;
        row.r = run.reduced_size;
        row.passes = static_cast<int>(run.passes.size());
        row.iterations = run.result.history.empty() ? 0 : run.result.history.back().iteration;
        row.precompute = design.timings.total;
        row.coefficients = design.timings.coefficients;
        row.refinement = design.timings.refinement;
        row.median_ms = run.median_iteration_ms;
        row.optimize = run.result.seconds;
        row.reduced_error = run.passes.back().reduced_error;
        row.full_error = run.passes.back().full_error;
        row.status = to_string(run.result.status);
        row.full_solve = run.full ? run.full->seconds : 0.0;
        worst_full = std::max(worst_full, row.full_error);
        rows.push_back(row);
        rows_json.push_back({{"cells", c},
                             {"tets", row.tets},
                             {"displacement_modes", k},
                             {"material_modes", m},
                             {"reduced_coordinates", row.r},
                             {"passes", row.passes},
                             {"iterations", row.iterations},
                             {"precomputation_seconds", row.precompute},
                             {"coefficient_seconds_last_pass", row.coefficients},
                             {"refinement_seconds", row.refinement},
                             {"median_iteration_ms", row.median_ms},
                             {"optimization_seconds", row.optimize},
                             {"reduced_handle_error", row.reduced_error},
                             {"full_space_handle_error", row.full_error},
                             {"full_space_solve_seconds", row.full_solve},
                             {"status", row.status}});
        std::printf(
            "  k %2d m %2d: r %3d, %d pass(es), %4d iterations, precompute %8.3f s, %8.3f ms/iteration, "
            "handle error reduced %.2e full %.2e\n",
            k, m, row.r, row.passes, row.iterations, row.precompute, row.median_ms, row.reduced_error,
            row.full_error);
        std::fflush(stdout);
      }
    if (no_full) continue;
    // The full-space design (existing path: log map in a smooth box, handle displacements as
    // design variables), run until its full-space handle error is at most the reduced runs'
    // worst. Its final E is checked the same way (handle force applied, mean tip displacement).
    const std::string full_design = R"({"parameter": "youngs_modulus", "granularity": "modes", "modes": )" +
                                    std::to_string(m_full) + R"(, "map": "log", "min": 1e3, "max": 1e8})";
    const ReducedDesign checker =
        build_reduced_design(parse(scene_text(c, reduced_design_key(2, 2), target, 1)));
    int iterations = 0;
    double error = 1.0, seconds = 0.0;
    std::vector<double> per_iteration;
    std::string status = "not run";
    for (int cap = 25; cap <= full_iterations; cap *= 2) {
      // Weights as in scenes/cantilever_handle.json: alpha = 1 / |fbar|^2, alpha beta = 1 / |ubar|^2.
      const Scene s =
          parse(scene_text(c, full_design, target, cap, 1e4 / (target_norm * target_norm), "ceres_lbfgs"));
      const InverseRun run = run_inverse_scene(
          s, (std::filesystem::temp_directory_path() / "reduced_design_bench_full").string());
      const FullSpaceCheck check = full_space_solve(checker, run.youngs_modulus);
      iterations = run.result.history.empty() ? 0 : run.result.history.back().iteration;
      seconds = run.result.seconds;
      per_iteration.clear();
      for (std::size_t i = 1; i < run.result.history.size(); ++i)
        per_iteration.push_back(run.result.history[i].seconds - run.result.history[i - 1].seconds);
      error = check.handle_errors.empty() ? 1.0 : check.handle_errors[0];
      status = to_string(run.result.status);
      if (run.result.status == OptimizerStatus::failed)
        std::printf("  full-space design failed: %s\n", run.result.message.c_str());
      if (error <= worst_full || run.result.converged()) break;
    }
    const double median_s = median_of(per_iteration);
    full_json.push_back({{"cells", c},
                         {"material_modes", m_full},
                         {"iterations", iterations},
                         {"seconds", seconds},
                         {"median_iteration_ms", 1e3 * median_s},
                         {"full_space_handle_error", error},
                         {"reduced_worst_full_space_error", worst_full},
                         {"status", status}});
    std::printf(
        "  full-space design (m %d): %d iterations, %.3f s, %.2f ms/iteration, handle error %.2e (%s)\n",
        m_full, iterations, seconds, 1e3 * median_s, error, status.c_str());
    std::fflush(stdout);
  }
  json["reduced"] = rows_json;
  json["full"] = full_json;

  std::printf("\n%6s %6s %3s %3s %4s %6s %5s %12s %10s %10s %10s %12s\n", "cells", "tets", "k", "m", "r",
              "passes", "iter", "precomp[s]", "ms/iter", "err red", "err full", "full solve[s]");
  for (const Row& r : rows)
    std::printf("%6d %6d %3d %3d %4d %6d %5d %12.3f %10.3f %10.2e %10.2e %12.3f\n", r.cells, r.tets, r.k, r.m,
                r.r, r.passes, r.iterations, r.precompute, r.median_ms, r.reduced_error, r.full_error,
                r.full_solve);
  for (const auto& f : full_json)
    std::printf("full-space design, cells %d: %.2f ms/iteration (%d iterations), handle error %.2e\n",
                f["cells"].get<int>(), f["median_iteration_ms"].get<double>(), f["iterations"].get<int>(),
                f["full_space_handle_error"].get<double>());
  return bench::write_report(out, json, "reduced_design_bench") ? 0 : 1;
}
