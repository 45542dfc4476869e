// Material design with a handle in reduced displacements and reduced materials (Xu, Li, Chen,
// Barbic 2015; problems/fem/reduced_design.hpp) against the full-space design of the same objective
// (problems/fem/full_space_design.hpp: same design w, same handle misfit, smoothness and positivity
// terms, same optimizer; every evaluation a full-space Newton solve and adjoint), at equal
// full-space error.
//
// Scene: a 10 x 1 x 1 StVK cantilever, 10 c x c x c cells (60 c^3 tets, --cells), clamped at
// x = 0; a handle on the tip face pushed down by a total force of 100 must reach a mean
// displacement ubar: the full-space response of the known graded design E = E0 (1 - 0.6 + 0.2
// y_2) (so a design exists). For each cell count and each (displacement modes, material modes)
// in --displacement-modes x --material-modes it reports the precomputation (modes, responses,
// derivatives, coefficients, refinements), the median milliseconds per optimizer iteration, the
// iterations and passes, and the full-space handle error |mean u - ubar| / |ubar| of the final
// design (its full-space solve). Then the full-space design with --material-modes' largest m runs
// until its full-space handle error (after every evaluation) is at most the best of the reduced
// runs with that m, or --full-iterations iterations; per reduced run with that m, the ratios in
// the same run: per iteration, optimization time to that run's full-space error, and total time
// to it (reduced: precomputation, optimization and the final full-space check; full space: the
// material modes and the optimization).
//
// --material neo_hookean (or corotated) designs that material instead: the reduced energy is
// then integrated by a cubature rule (problems/fem/reduced_design_cubature.hpp) of at most
// --cubature-elements elements, whose size, training error and fitting time are reported; the
// full-space checks use exact Newton Hessians and a relative tolerance of 1e-6 (at E = 1e6 the
// Neo-Hookean full-space Newton stalls near 2e-7 relative: its line search meets the energy's
// round-off). The full-space Neo-Hookean design (StaticFunctional, Newton from rest at full
// load) does not converge at its start on this beam; use --no-full. --material stvk with
// --cubature-elements N uses a rule for StVK too, against the exact polynomial.
//
// usage: reduced_design_bench [--quick] [--cells 2,4] [--displacement-modes 4,8]
//          [--material-modes 4,8] [--max-iterations 100] [--full-iterations 200] [--refinements 2] [--out
//          FILE]
//          [--no-full] [--material stvk|neo_hookean|corotated] [--cubature-elements N]
//          [--cubature-candidates N] [--targets N]
//
// --targets N: then N - 1 more targets (full-space responses of other graded designs) are given
// to the kept design (the last grid point with the most material modes) with set_handle_targets
// and designed from w = 0 without another precomputation, each against a full-space design to
// its full-space error; the cumulative ratio (full-space time over reduced time, the reduced
// precomputation counted once) shows how the precomputation pays off when a mesh is designed
// more than once, as in the interactive loop.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bench_cli.hpp"
#include "problems/fem/full_space_design.hpp"
#include "problems/fem/reduced_design.hpp"

namespace tailor::bench::reduced_design_bench {

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

// The material of the scene and its solver section.
std::string g_material = "stvk";

// The scene; `design` is the inverse.design object.
std::string scene_text(int c, const std::string& design, const std::string& target, int max_iterations) {
  const std::string solver =
      g_material == "stvk" ? "" : R"("solver": {"hessian": "exact", "relative_tolerance": 1e-6},)";
  return R"({"name": "reduced_design_bench",
  "mesh": {"box": {"min": [0, 0, 0], "max": [10, 1, 1], "cells": [)" +
         std::to_string(10 * c) + ", " + std::to_string(c) + ", " + std::to_string(c) + R"(]}},
  "materials": [{"elements": "all", "model": ")" +
         g_material + R"(", "youngs_modulus": 1e6, "poisson_ratio": 0.3, "density": 1000}],
  "dirichlet": [{"vertices": {"plane": {"axis": "x", "value": 0}}}], )" +
         solver + R"(
  "inverse": {"design": )" +
         design + R"(,
    "objective": [{"type": "handles", "handles": [
      {"vertices": {"plane": {"axis": "x", "value": 10}}, "force": [0, 0, -100], "displacement": )" +
         target + R"(}]}],
    "optimizer": {"backend": "nlopt_lbfgs", "max_iterations": )" +
         std::to_string(max_iterations) + R"(, "gradient_tolerance": 1e-8, "objective_tolerance": 1e-12}}})";
}

// The graded designs whose full-space responses are the targets: (w_1, w_2) of target i, E =
// E0 (1 + w_1 + w_2 y_2) (y_2 of order 1: E > 0 everywhere). Designs whose full-space solve
// (Newton from rest at full load) fails are skipped; there are 8.
constexpr int kGradedDesigns = 8;
std::pair<double, double> graded_design(int i) {
  static const std::pair<double, double> designs[kGradedDesigns] = {
      {-0.6, 0.2},  {-0.5, 0.1},  {-0.4, -0.1},  {-0.3, 0.15},
      {-0.5, -0.1}, {-0.2, -0.1}, {-0.45, 0.05}, {-0.35, -0.05}};
  return designs[i];
}

int g_cubature_elements = 0;    // 0: the default rule size (and none for StVK)
int g_cubature_candidates = 0;  // 0: every element scored in each greedy step

std::string reduced_design_key(int k, int m, int refinements = 2) {
  std::string cubature;
  // A cubature section for StVK only with a rule size (else its exact polynomial).
  if (g_cubature_elements > 0 || (g_cubature_candidates > 0 && g_material != "stvk")) {
    cubature = R"(, "cubature": {"candidates": )" + std::to_string(g_cubature_candidates);
    if (g_cubature_elements > 0) cubature += R"(, "elements": )" + std::to_string(g_cubature_elements);
    cubature += "}";
  }
  return R"({"parameter": "youngs_modulus", "granularity": "modes", "modes": )" + std::to_string(m) +
         R"(, "map": "identity", "reduction": {"displacement_modes": )" + std::to_string(k) +
         R"(, "smoothness": 1e-4, "refinements": )" + std::to_string(refinements) + cubature + "}}";
}

Scene parse(const std::string& text) { return parse_scene(text, "reduced_design_bench.json", "."); }

struct Row {
  int cells = 0, tets = 0, k = 0, m = 0, r = 0, passes = 0, iterations = 0;
  double precompute = 0, coefficients = 0, refinement = 0, median_ms = 0, optimize = 0;
  double reduced_error = 0, full_error = 0, full_solve = 0;
  int cubature_elements = 0;  // 0: the exact polynomial
  double cubature_error = 0, cubature_seconds = 0;
  std::string status;
};

struct FullRow {
  int cells = 0, m = 0, iterations = 0, evaluations = 0;
  double median_ms = 0, best_error = 0, goal = 0, seconds = 0, material_modes_seconds = 0;
  std::string status;
};

// The full-space functional, recording after every evaluation the seconds since the first one
// started and the full-space handle error (the largest over the handles).
class EvaluationLog final : public ReducedFunctional {
 public:
  explicit EvaluationLog(FullSpaceDesignFunctional& inner) : inner_(inner) {}
  int size() const override { return inner_.size(); }
  double value(const Vector& z) override { return record(inner_.value(z)); }
  double value_and_gradient(const Vector& z, Vector& gradient) override {
    return record(inner_.value_and_gradient(z, gradient));
  }
  const FunctionalCounters& counters() const override { return inner_.counters(); }
  // The seconds when the error was first at most `error`; negative when it never was.
  double seconds_to(double error) const {
    for (const auto& [seconds, e] : trace_)
      if (e <= error) return seconds;
    return -1.0;
  }
  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  double best_error() const { return best_; }
  const std::vector<std::pair<double, double>>& trace() const { return trace_; }
  int count() const { return static_cast<int>(trace_.size()); }

 private:
  double record(double value) {
    const std::vector<double> errors = inner_.handle_errors();
    const double error = *std::max_element(errors.begin(), errors.end());
    best_ = std::min(best_, error);
    trace_.emplace_back(seconds(), error);
    return value;
  }
  FullSpaceDesignFunctional& inner_;
  Clock::time_point start_ = Clock::now();
  std::vector<std::pair<double, double>> trace_;
  double best_ = 1e300;
};

}  // namespace

int run(int argc, char** argv) {
  std::vector<int> cells{2, 4}, ks{4, 8}, ms{4, 8};
  int max_iterations = 100, full_iterations = 200, refinements = 2, num_targets = 1;
  bool quick = false, no_full = false;
  std::string out = "bench_reduced_design.json";
  bench::Cli cli("reduced_design_bench", "reduced vs full-space material design with a handle");
  cli.integers("--cells", cells, "cells through the beam's height (60 c^3 tets)", 1);
  cli.integers("--displacement-modes", ks, "linear vibration modes in the reduced basis", 1);
  cli.integers("--material-modes", ms, "Laplacian material modes", 2);
  cli.integer("--max-iterations", max_iterations, "optimizer iterations per pass (and full design)", 1);
  cli.integer("--full-iterations", full_iterations, "iteration cap of the full-space design", 1);
  cli.integer("--refinements", refinements, "basis refinements at most (reduction.refinements)", 0);
  cli.integer("--targets", num_targets,
              "targets designed on one precomputation (the last grid point with the most material modes)", 1);
  cli.flag("--quick", quick, "cells 2, one grid point (4 x 4)");
  cli.flag("--no-full", no_full, "skip the full-space design");
  cli.choice("--material", g_material, "the beam's material (non-StVK: cubature)",
             {"stvk", "neo_hookean", "corotated"});
  cli.integer("--cubature-elements", g_cubature_elements, "cubature rule size at most (0: the default)", 0);
  cli.integer("--cubature-candidates", g_cubature_candidates,
              "elements scored per greedy step of the cubature fit, a random subset (0: every element)", 0);
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  if (quick) cells = {2}, ks = {4}, ms = {4};

  bench::Json json = bench::report("reduced_design");
  bench::Json rows_json = bench::Json::array(), full_json = bench::Json::array();
  std::vector<Row> rows;
  std::vector<FullRow> full_rows;
  const int m_full = *std::max_element(ms.begin(), ms.end());
  for (int c : cells) {
    // The targets: the full-space responses of graded designs w* (first two modes); the first
    // for the grid, the others for --targets.
    const ReducedDesign probe =
        build_reduced_design(parse(scene_text(c, reduced_design_key(2, 2), "[0, 0, -1]", 1)));
    std::vector<Vector> targets;
    for (int i = 0; static_cast<int>(targets.size()) < num_targets; ++i) {
      if (i >= kGradedDesigns) {
        if (!targets.empty()) break;  // fewer targets than asked for
        std::cerr << "no graded design's full-space solve converged\n";
        return 1;
      }
      const auto [w0, w1] = graded_design(i);
      Vector w = Vector::Zero(probe.num_design());
      w[0] = w0;
      w[1] = w1;
      const FullSpaceCheck truth = full_space_check(probe, w);
      if (!truth.converged) {
        // (Newton from rest at full load: some graded designs need a load ramp on fine meshes.)
        std::printf("cells %d: graded design %d (w = %g, %g) skipped: its full-space solve failed (%s)\n", c,
                    i + 1, w0, w1, truth.message.c_str());
        continue;
      }
      Vector mean = Vector::Zero(3);
      for (int v : probe.handles[0].vertices) mean += truth.displacement.segment(3 * v, 3);
      mean /= static_cast<double>(probe.handles[0].vertices.size());
      targets.push_back(mean);
    }
    const std::string target =
        "[" + num(targets[0][0]) + ", " + num(targets[0][1]) + ", " + num(targets[0][2]) + "]";
    std::printf("cells %d: %d tets, target mean tip displacement %s\n", c, probe.setup.mesh.num_elements(),
                target.c_str());
    double best_full = 1e300;           // of the runs with m_full material modes
    std::optional<ReducedDesign> kept;  // the last design with m_full material modes
    for (int k : ks)
      for (int m : ms) {
        ReducedDesign design = build_reduced_design(
            parse(scene_text(c, reduced_design_key(k, m, refinements), target, max_iterations)));
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
        if (run.cubature) {
          row.cubature_elements = run.cubature->elements;
          row.cubature_error = run.cubature->training_error;
          row.cubature_seconds = design.timings.cubature;
        }
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
                             {"precomputation_parts_seconds",
                              {{"setup", design.timings.setup},
                               {"displacement_modes", design.timings.displacement_modes},
                               {"responses", design.timings.responses},
                               {"modal_derivatives", design.timings.modal_derivatives},
                               {"material_modes", design.timings.material_modes},
                               {"coefficients_last_pass", design.timings.coefficients}}},
                             {"refinement_seconds", row.refinement},
                             {"median_iteration_ms", row.median_ms},
                             {"optimization_seconds", row.optimize},
                             {"reduced_handle_error", row.reduced_error},
                             {"full_space_handle_error", row.full_error},
                             {"full_space_solve_seconds", row.full_solve},
                             {"material", g_material},
                             {"cubature",
                              {{"elements", row.cubature_elements},
                               {"training_error", row.cubature_error},
                               {"seconds_all_passes", row.cubature_seconds}}},
                             {"status", row.status}});
        std::printf(
            "  k %2d m %2d: r %3d, %d pass(es), %4d iterations, precompute %8.3f s, %8.3f ms/iteration, "
            "handle error reduced %.2e full %.2e\n",
            k, m, row.r, row.passes, row.iterations, row.precompute, row.median_ms, row.reduced_error,
            row.full_error);
        bench::Json by_pass = bench::Json::array();
        std::printf("           by pass (r: ms/iteration):");
        for (const ReducedDesignPass& pass : run.passes) {
          by_pass.push_back({{"reduced_coordinates", pass.reduced_size},
                             {"iterations", pass.iterations},
                             {"median_iteration_ms", pass.median_iteration_ms}});
          std::printf(" %d: %.3f", pass.reduced_size, pass.median_iteration_ms);
        }
        std::printf("\n");
        rows_json.back()["passes_detail"] = by_pass;
        if (run.cubature)
          std::printf("           cubature %d of %d elements, training error %.2e, %.3f s over the passes\n",
                      row.cubature_elements, run.cubature->mesh_elements, row.cubature_error,
                      row.cubature_seconds);
        std::fflush(stdout);
        if (m == m_full) {
          best_full = std::min(best_full, row.full_error);
          kept.emplace(std::move(design));
        }
      }
    if (!kept) continue;
    // The full-space design of the same objective (problems/fem/full_space_design.hpp): the same w
    // over the same m_full material modes, the same optimizer and settings, every evaluation a
    // full-space Newton solve and its adjoint; run until its full-space handle error is at most
    // `goal` (or --full-iterations iterations).
    struct FullRun {
      FullRow row;
      std::vector<std::pair<double, double>> trace;  // (seconds, full-space error) per evaluation
      double seconds_to(double error) const {
        for (const auto& [seconds, e] : trace)
          if (e <= error) return seconds;
        return -1.0;
      }
    };
    const auto full_design = [&](double goal) {
      FullSpaceDesignFunctional full(*kept);
      EvaluationLog evaluations(full);
      OptimizerOptions options = kept->optimizer;
      options.max_iterations = full_iterations;
      options.checkpoint_every = 1;
      options.on_checkpoint = [&evaluations, goal](const OptimizerCheckpoint&) {
        if (evaluations.seconds_to(goal) >= 0.0)
          throw std::runtime_error("reached the reduced design's full-space error");
      };
      const OptimizerResult result =
          minimize(evaluations, Vector::Zero(kept->num_design()), Bounds{}, {}, options);
      std::vector<double> per_iteration;
      for (std::size_t i = 1; i < result.history.size(); ++i)
        per_iteration.push_back(result.history[i].seconds - result.history[i - 1].seconds);
      FullRun run;
      FullRow& f = run.row;
      f.cells = c;
      f.m = m_full;
      f.iterations = result.history.empty() ? 0 : result.history.back().iteration;
      f.evaluations = evaluations.count();
      f.median_ms = 1e3 * median_of(per_iteration);
      f.best_error = evaluations.best_error();
      f.goal = goal;
      f.seconds = evaluations.seconds();
      f.material_modes_seconds = kept->timings.material_modes;
      f.status =
          evaluations.seconds_to(goal) >= 0.0 ? "reached" : to_string(result.status) + ": " + result.message;
      run.trace = evaluations.trace();
      return run;
    };
    std::optional<FullRun> first_full;
    if (!no_full) {
      const FullRun& full = first_full.emplace(full_design(best_full));
      const FullRow& f = full.row;
      full_rows.push_back(f);
      bench::Json ratios = bench::Json::array();
      for (const Row& r : rows) {
        if (r.cells != c || r.m != m_full) continue;
        // The full-space design's time to this row's full-space error (its whole run when it never
        // got there: the ratios are then lower bounds).
        const double to_error = full.seconds_to(r.full_error);
        const bool reached = to_error >= 0.0;
        const double full_seconds = reached ? to_error : f.seconds;
        const double reduced_total = r.precompute + r.optimize + r.full_solve;
        const double full_total = f.material_modes_seconds + full_seconds;
        ratios.push_back({{"displacement_modes", r.k},
                          {"full_space_error", r.full_error},
                          {"reached", reached},
                          {"full_seconds_to_error", full_seconds},
                          {"per_iteration", f.median_ms / r.median_ms},
                          {"optimization_to_equal_error", full_seconds / r.optimize},
                          {"total_to_equal_error", full_total / reduced_total},
                          {"reduced_total_seconds", reduced_total},
                          {"full_total_seconds", full_total}});
        std::printf(
            "  k %2d m %2d against full space at error %.2e: %.0fx per iteration, %.0fx in optimization "
            "time, "
            "%.1fx in total (%.2f s reduced with precomputation and check, %.2f s full%s)\n",
            r.k, r.m, r.full_error, f.median_ms / r.median_ms, full_seconds / r.optimize,
            full_total / reduced_total, reduced_total, full_total,
            reached ? "" : "; full space did not get there: lower bounds");
      }
      full_json.push_back({{"cells", c},
                           {"material_modes", m_full},
                           {"iterations", f.iterations},
                           {"evaluations", f.evaluations},
                           {"median_iteration_ms", f.median_ms},
                           {"goal_full_space_error", f.goal},
                           {"seconds", f.seconds},
                           {"best_full_space_error", f.best_error},
                           {"material_modes_seconds", f.material_modes_seconds},
                           {"status", f.status},
                           {"ratios", ratios}});
      std::printf(
          "  full-space design (m %d): %d iterations, %d evaluations, %.2f ms/iteration, error %.2e in %.3f "
          "s "
          "(goal %.2e, %s)\n",
          m_full, f.iterations, f.evaluations, f.median_ms, f.best_error, f.seconds, f.goal,
          f.status.c_str());
      std::fflush(stdout);
    }
    if (static_cast<int>(targets.size()) < 2) continue;
    // --targets: the same design (the last grid point with m_full modes, its precomputation and
    // refinements kept) given new targets (set_handle_targets), each designed from w = 0 again,
    // as a user moving the handle's target would; each against a full-space design to the same
    // full-space error. Amortized: the precomputation once, then per target the reduced loop's
    // wall time (optimization, full-space checks, refinements).
    const Row& first = [&]() -> const Row& {
      for (auto it = rows.rbegin(); it != rows.rend(); ++it)
        if (it->cells == c && it->m == m_full) return *it;
      throw std::logic_error("no row with m_full");
    }();
    double reduced_sum = first.precompute + first.optimize + first.full_solve;
    // The first target's full-space time to the kept row's error, as in the ratios above (its
    // whole run when it never got there).
    double full_sum = 0.0;
    if (first_full) {
      const double to_error = first_full->seconds_to(first.full_error);
      full_sum =
          first_full->row.material_modes_seconds + (to_error >= 0.0 ? to_error : first_full->row.seconds);
    }
    const double first_full_total = full_sum;
    bench::Json targets_json = bench::Json::array();
    std::printf("  new targets on the design of k %d m %d (precomputation %.2f s, kept):\n", first.k, m_full,
                first.precompute);
    std::printf("  %6s %14s %10s %10s %10s %12s %12s %14s\n", "target", "reduced [s]", "iter", "r",
                "err full", "full [s]", "cumul. ratio", "full reached");
    std::printf("  %6d %14.3f %10d %10d %10.2e %12.3f %12.1f %14s\n", 1, reduced_sum, first.iterations,
                first.r, first.full_error, full_sum, no_full ? 0.0 : full_sum / reduced_sum,
                no_full ? "-" : first_full->row.status.c_str());
    for (int i = 1; i < static_cast<int>(targets.size()); ++i) {
      set_handle_targets(*kept, {targets[static_cast<std::size_t>(i)]});
      const auto t0 = Clock::now();
      const ReducedDesignRun run = run_reduced_design(*kept, "");
      const double reduced_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
      const double full_error = run.passes.back().full_error;
      reduced_sum += reduced_seconds;
      bench::Json item = {
          {"target", i + 1},
          {"target_displacement", {targets[i][0], targets[i][1], targets[i][2]}},
          {"reduced_wall_seconds", reduced_seconds},
          {"optimization_seconds", run.result.seconds},
          {"iterations", run.result.history.empty() ? 0 : run.result.history.back().iteration},
          {"passes", run.passes.size()},
          {"reduced_coordinates", run.reduced_size},
          {"median_iteration_ms", run.median_iteration_ms},
          {"full_space_handle_error", full_error},
          {"reduced_cumulative_seconds", reduced_sum}};
      double full_seconds = 0.0;
      bool reached = false;
      if (!no_full) {
        const FullRun full = full_design(full_error);
        const double to_error = full.seconds_to(full_error);
        reached = to_error >= 0.0;
        full_seconds = reached ? to_error : full.row.seconds;
        full_sum += full_seconds;
        item["full_seconds_to_error"] = full_seconds;
        item["full_reached"] = reached;
        item["full_cumulative_seconds"] = full_sum;
        item["cumulative_ratio"] = full_sum / reduced_sum;
      }
      targets_json.push_back(item);
      std::printf("  %6d %14.3f %10d %10d %10.2e %12.3f %12.1f %14s\n", i + 1, reduced_seconds,
                  item["iterations"].get<int>(), run.reduced_size, full_error, full_seconds,
                  no_full ? 0.0 : full_sum / reduced_sum,
                  no_full ? "-" : (reached ? "yes" : "no (lower bound)"));
      std::fflush(stdout);
    }
    json["targets"] = {{"cells", c},
                       {"displacement_modes", first.k},
                       {"material_modes", m_full},
                       {"first_reduced_total_seconds", first.precompute + first.optimize + first.full_solve},
                       {"first_full_total_seconds", first_full_total},
                       {"reduced_cumulative_seconds", reduced_sum},
                       {"full_cumulative_seconds", full_sum},
                       {"more", targets_json}};
  }
  json["reduced"] = rows_json;
  json["full"] = full_json;

  std::printf("\n%6s %6s %3s %3s %4s %6s %5s %12s %10s %10s %10s %12s\n", "cells", "tets", "k", "m", "r",
              "passes", "iter", "precomp[s]", "ms/iter", "err red", "err full", "full solve[s]");
  for (const Row& r : rows)
    std::printf("%6d %6d %3d %3d %4d %6d %5d %12.3f %10.3f %10.2e %10.2e %12.3f\n", r.cells, r.tets, r.k, r.m,
                r.r, r.passes, r.iterations, r.precompute, r.median_ms, r.reduced_error, r.full_error,
                r.full_solve);
  for (const FullRow& f : full_rows)
    std::printf(
        "full-space design, cells %d, m %d: %.2f ms/iteration, %d iterations, error %.2e after %.3f s (%s)\n",
        f.cells, f.m, f.median_ms, f.iterations, f.best_error, f.seconds, f.status.c_str());
  return bench::write_report(out, json, "reduced_design_bench") ? 0 : 1;
}

}  // namespace tailor::bench::reduced_design_bench
