// Reduced material design with Laplacian material modes (Xu, Li, Chen, Barbic 2015) against
// the full per-element design: speed and recovery error together.
//
// Scenes: scenes/inclusion_recovery_small.json (3456 tets) and scenes/inclusion_recovery.json
// (49152 tets): a Neo-Hookean block whose true Young's modulus is a gradient plus a 5x stiffer
// sphere, observed on its surface only. For each scene and setting:
//   full      one variable per element (granularity "modes" with "full": the same smooth box
//             on log E, no reduction), capped by --full-time-limit and --max-iterations,
//   r modes   r in --modes (default 5, 10, 20, 40, 80) with nlopt_lbfgs, and the --backends
//             (default ipopt, ceres_lbfgs, gradient_descent) at r = --backend-modes (20),
//             capped by --max-iterations and --time-limit seconds (default none),
// it reports: wall = modes + optimization seconds (the synthetic truth solve is excluded),
// Newton iterations per forward solve, the load average (the machine may be shared),
// iterations, per-iteration forward / adjoint milliseconds, the eigen solve's seconds, the
// final objective and the volume-weighted relative L2 error of E against the truth.
// Writes JSON (--out, default bench_material_modes.json, with every evaluation's time and error),
// per scene a PNG of error against wall time along each run (--plot, default
// bench_material_modes.png -> bench_material_modes_small.png, ..._large.png) and prints a table,
// then per reduced run its speed-up over the full design and how soon it reached the full
// design's final error. Run with
// OPENBLAS_NUM_THREADS=1 on a shared machine (BLAS threads fight over the cores otherwise).
// --reuse-factorization / --no-reuse-factorization override the scenes' solver.reuse_factorization (on in the
// large scene, off in the small one, where a factorization is cheap and CG steps do not pay off): Newton
// preconditions CG with its kept factorization instead of factorizing every iteration.
// --no-full skips the full design (e.g. to time reduced runs on the large scene alone).
//
// usage: material_modes_bench [--quick] [--scenes small,large] [--modes 5,10,20,40,80]
//          [--backends ipopt,ceres_lbfgs,gradient_descent] [--backend-modes 20] [--max-iterations 200]
//          [--full-time-limit 600] [--time-limit 0] [--scene-dir scenes]
//          [--out FILE] [--plot FILE] [--reuse-factorization | --no-reuse-factorization] [--no-full]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "problems/fem/inverse_problem.hpp"
#include "problems/json_text.hpp"
#include "problems/plot/line_plot.hpp"
#include "tailor_version.hpp"

namespace tailor::bench::material_modes_bench {

using namespace tailor;

namespace {

struct Setting {
  std::string scene;         // "small" or "large"
  std::optional<int> modes;  // nullopt: full
  OptimizerBackend backend = OptimizerBackend::nlopt_lbfgs;
};

struct Row {
  std::string scene, backend, status;
  int tets = 0, design = 0, iterations = 0, evaluations = 0;
  std::string modes;  // "full" or r
  double modes_s = 0, optimization_s = 0, wall_s = 0, forward_ms = 0, adjoint_ms = 0, objective = 0,
         error = 0, initial_error = 0;
  bool capped = false;                           // stopped by an iteration or time cap
  std::vector<double> history_s, history_error;  // per evaluation: wall seconds (with modes), E error
  int newton_iterations = 0;                     // summed over the forward solves
  int factorizations = 0;                        // Newton's numeric factorizations, summed likewise
  double load_average = 0.0;                     // 1-minute load average when the run ended
};

struct Settings {
  std::vector<std::string> scenes = {"small", "large"};
  std::vector<int> modes = {5, 10, 20, 40, 80};
  int backend_modes = 20;
  std::vector<OptimizerBackend> backends = {OptimizerBackend::ipopt, OptimizerBackend::ceres_lbfgs,
                                            OptimizerBackend::gradient_descent};
  int max_iterations = 200;
  double full_time_limit = 600.0;
  double time_limit = 0.0;                  // of the reduced runs; 0 = none
  std::optional<bool> reuse_factorization;  // overrides solver.reuse_factorization when set
  bool full = true;                         // run the full design
  std::string scene_dir = "scenes", out = "bench_material_modes.json", plot = "bench_material_modes.png";
};

std::string scene_file(const Settings& settings, const std::string& scene) {
  return settings.scene_dir +
         (scene == "small" ? "/inclusion_recovery_small.json" : "/inclusion_recovery.json");
}

// The functional as the optimizer sees it, recording after every evaluation the wall time since
// the start (plus the eigen solve) and the recovery error of the best design evaluated so far.
class RecordingFunctional final : public ReducedFunctional {
 public:
  RecordingFunctional(const InverseProblem& problem, double modes_s, Row& row)
      : problem_(problem), modes_s_(modes_s), row_(row), start_(std::chrono::steady_clock::now()) {}
  int size() const override { return problem_.functional->size(); }
  double value(const Vector& z) override { return record(z, problem_.functional->value(z)); }
  double value_and_gradient(const Vector& z, Vector& gradient) override {
    return record(z, problem_.functional->value_and_gradient(z, gradient));
  }
  const FunctionalCounters& counters() const override { return problem_.functional->counters(); }

 private:
  double record(const Vector& z, double value) {
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    row_.history_s.push_back(modes_s_ + t);
    if (problem_.functional->counters().forward_solves != solves_) {
      solves_ = problem_.functional->counters().forward_solves;
      row_.newton_iterations += problem_.functional->last_newton().iterations;
      row_.factorizations += problem_.functional->last_newton().factorizations();
    }
    // The error of the best design so far (lowest J): what stopping now would return; trial
    // points of line searches would otherwise show as spikes.
    if (value < best_value_) {
      best_value_ = value;
      best_error_ = field_error(problem_.setup.mesh, problem_.youngs_modulus(z), problem_.truth).relative_l2;
    }
    row_.history_error.push_back(best_error_);
    return value;
  }
  const InverseProblem& problem_;
  double modes_s_;
  Row& row_;
  std::chrono::steady_clock::time_point start_;
  int solves_ = 0;
  double best_value_ = std::numeric_limits<double>::infinity(), best_error_ = 0.0;
};

// The machine's 1-minute load average (0 when unknown): the bench shares the cores.
double load_average() {
  std::ifstream in("/proc/loadavg");
  double load = 0.0;
  in >> load;
  return load;
}

// Seconds until the run's error first reached `error` (infinity when never).
double time_to_error(const Row& row, double error) {
  for (std::size_t k = 0; k < row.history_s.size(); ++k)
    if (row.history_error[k] <= error) return row.history_s[k];
  return std::numeric_limits<double>::infinity();
}

Row run(const Settings& settings, const Setting& setting) {
  Scene scene = read_scene(scene_file(settings, setting.scene));
  if (settings.reuse_factorization)
    scene.solver.newton.reuse_factorization =
        *settings.reuse_factorization ? FactorReuse::on : FactorReuse::off;
  auto spec = std::make_shared<InverseSpec>(*scene.inverse);
  spec->design.granularity = DesignGranularity::modes;
  spec->design.modes = setting.modes;
  spec->design.output_modes = 0;
  spec->optimizer.backend = setting.backend;
  spec->optimizer.max_iterations = settings.max_iterations;
  spec->optimizer.time_limit_seconds = setting.modes ? settings.time_limit : settings.full_time_limit;
  scene.inverse = spec;

  const std::unique_ptr<InverseProblem> problem = build_inverse_problem(scene);
  Row row;
  RecordingFunctional recording(*problem, problem->modal ? problem->modal->seconds : 0.0, row);
  OptimizerResult result = minimize(recording, problem->z0, problem->bounds, {}, spec->optimizer);
  const FunctionalCounters& counters = problem->functional->counters();

  row.scene = setting.scene;
  row.backend = to_string(setting.backend);
  row.status = to_string(result.status);
  row.capped =
      result.status == OptimizerStatus::max_iterations || result.status == OptimizerStatus::time_limit;
  row.tets = problem->setup.mesh.num_elements();
  row.design = problem->num_design();
  row.modes = setting.modes ? std::to_string(*setting.modes) : "full";
  row.iterations = result.history.empty() ? 0 : result.history.back().iteration;
  row.evaluations = result.evaluations;
  row.modes_s = problem->modal ? problem->modal->seconds : 0.0;
  row.optimization_s = result.seconds;
  row.wall_s = row.modes_s + row.optimization_s;
  const double per = std::max(1, row.iterations);
  row.forward_ms = 1e3 * counters.forward_seconds / per;
  row.adjoint_ms = 1e3 * counters.adjoint_seconds / per;
  row.objective = result.objective;
  row.load_average = load_average();
  row.error = field_error(problem->setup.mesh, problem->youngs_modulus(result.z), problem->truth).relative_l2;
  row.initial_error =
      field_error(problem->setup.mesh, problem->youngs_modulus(problem->z0), problem->truth).relative_l2;
  return row;
}

void print_row(const Row& r) {
  std::printf("%-6s %6d %5s %-17s %5d %5d %6.1f %6.1f %9.2f %8.3f %9.1f %9.1f %12.5e %8.4f %4.1f %s\n",
              r.scene.c_str(), r.tets, r.modes.c_str(), r.backend.c_str(), r.iterations, r.evaluations,
              static_cast<double>(r.newton_iterations) / std::max(1, r.evaluations),
              static_cast<double>(r.factorizations) / std::max(1, r.evaluations), r.wall_s, r.modes_s,
              r.forward_ms, r.adjoint_ms, r.objective, r.error, r.load_average,
              (r.status + (r.capped ? " (capped)" : "")).c_str());
  std::fflush(stdout);
}

bench::Json write_json(const Settings& settings, const std::vector<Row>& rows) {
  bench::Json json = bench::report("material_modes");
  const char* threads = std::getenv("OPENBLAS_NUM_THREADS");
  json["openblas_num_threads"] = threads ? threads : "unset";
  json["max_iterations"] = settings.max_iterations;
  json["full_time_limit_s"] = settings.full_time_limit;
  bench::Json results = bench::Json::array();
  for (const Row& r : rows)
    results.push_back({{"scene", r.scene},
                       {"tets", r.tets},
                       {"modes", r.modes},
                       {"design_variables", r.design},
                       {"backend", r.backend},
                       {"status", r.status},
                       {"capped", r.capped},
                       {"iterations", r.iterations},
                       {"evaluations", r.evaluations},
                       {"wall_s", r.wall_s},
                       {"modes_s", r.modes_s},
                       {"optimization_s", r.optimization_s},
                       {"forward_ms_per_iteration", r.forward_ms},
                       {"adjoint_ms_per_iteration", r.adjoint_ms},
                       {"newton_iterations", r.newton_iterations},
                       {"newton_factorizations", r.factorizations},
                       {"load_average", r.load_average},
                       {"objective", r.objective},
                       {"relative_l2_error", r.error},
                       {"initial_relative_l2_error", r.initial_error},
                       {"history_s", bench::array(r.history_s)},
                       {"history_relative_l2_error", bench::array(r.history_error)}});
  json["results"] = results;
  return json;
}

// Per scene, PLOT_scene.png (PLOT = --plot without ".png"): the recovery error of the best design
// so far (lowest J) against log10 of the wall time, after every evaluation, one curve per run.
std::vector<std::string> write_plots(const Settings& settings, const std::vector<Row>& rows) {
  static const Rgb palette[] = {{0, 0, 0},       {31, 119, 180},  {230, 110, 20}, {44, 160, 44},
                                {214, 39, 40},   {148, 103, 189}, {140, 86, 75},  {227, 119, 194},
                                {127, 127, 127}, {188, 189, 34}};
  std::string stem = settings.plot;
  if (stem.size() > 4 && stem.substr(stem.size() - 4) == ".png") stem.resize(stem.size() - 4);
  std::vector<std::string> paths;
  for (const std::string& scene : settings.scenes) {
    LinePlot plot;
    plot.title = scene + ": recovery error vs wall time";
    plot.x_label = "log10 wall time [s] (modes + optimization)";
    plot.y_label = "relative L2 error of E";
    plot.width = 1000;
    plot.height = 600;
    int c = 0;
    for (const Row& r : rows) {
      if (r.scene != scene) continue;
      LineSeries series{
          (r.modes == "full" ? "full" : "r=" + r.modes) + " " + r.backend, palette[c++ % 10], {}, {}};
      for (std::size_t k = 0; k < r.history_s.size(); ++k) {
        series.x.push_back(std::log10(std::max(r.history_s[k], 1e-3)));
        series.y.push_back(r.history_error[k]);
      }
      plot.series.push_back(std::move(series));
    }
    if (plot.series.empty()) continue;
    paths.push_back(stem + "_" + scene + ".png");
    write_line_plot_png(paths.back(), plot);
  }
  return paths;
}

}  // namespace

int run(int argc, char** argv) {
  Settings settings;
  bool quick = false;
  std::vector<std::string> backends;
  bench::Cli cli("material_modes_bench",
                 "Reduced material design with Laplacian material modes vs the full design.");
  cli.flag("--quick", quick,
           "the small scene, r = 5 and 20, no back-end comparison, full design capped at 20 s");
  cli.choices("--scenes", settings.scenes, "scenes to run", {"small", "large"});
  cli.integers("--modes", settings.modes, "material mode counts r (nlopt_lbfgs)", 1);
  cli.names("--backends", backends,
            "back-ends compared at r = --backend-modes (default ipopt,ceres_lbfgs,gradient_descent)",
            "NAME[,...]", [](const std::string& name) -> std::string {
              try {
                parse_optimizer_backend(name);
                return {};
              } catch (const std::invalid_argument& e) {
                return e.what();
              }
            });
  cli.integer("--backend-modes", settings.backend_modes, "r of the back-end comparison", 1);
  cli.integer("--max-iterations", settings.max_iterations, "optimizer iteration cap of every run", 1);
  cli.number("--full-time-limit", settings.full_time_limit, "time cap of the full design [s]", 0.0);
  cli.number("--time-limit", settings.time_limit, "time cap of the reduced runs [s] (0: none)", 0.0,
             /*inclusive=*/true);
  cli.text("--scene-dir", settings.scene_dir, "folder of the inclusion_recovery scenes", "DIR");
  cli.out(settings.out);
  cli.text("--plot", settings.plot, "PNG stem: PLOT_small.png, PLOT_large.png", "FILE");
  cli.on_off(
      "--reuse-factorization", "--no-reuse-factorization",
      [&settings](bool on) { settings.reuse_factorization = on; },
      "Newton preconditions CG with its kept factorization (default: as in each scene)",
      "Newton factorizes every iteration");
  cli.flag(
      "--no-full", [&settings] { settings.full = false; }, "skip the full design");
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  if (!backends.empty()) {
    settings.backends.clear();
    for (const std::string& b : backends) settings.backends.push_back(parse_optimizer_backend(b));
  }
  if (quick) {  // the small scene, two mode counts, one back-end, a short cap on the full design
    settings.scenes = {"small"};
    settings.modes = {5, 20};
    settings.full_time_limit = std::min(settings.full_time_limit, 20.0);
  }

  std::vector<Setting> plan;
  for (const std::string& scene : settings.scenes) {
    if (settings.full) plan.push_back({scene, std::nullopt, OptimizerBackend::nlopt_lbfgs});
    for (int r : settings.modes) plan.push_back({scene, r, OptimizerBackend::nlopt_lbfgs});
    if (!quick)
      for (OptimizerBackend b : settings.backends) plan.push_back({scene, settings.backend_modes, b});
  }

  std::printf(
      "tailor %s: material modes vs full design (OPENBLAS_NUM_THREADS=%s; caps: %d iterations, full %g s; "
      "reuse_factorization %s)\n",
      version_string, std::getenv("OPENBLAS_NUM_THREADS") ? std::getenv("OPENBLAS_NUM_THREADS") : "unset",
      settings.max_iterations, settings.full_time_limit,
      !settings.reuse_factorization   ? "as in the scenes"
      : *settings.reuse_factorization ? "on"
                                      : "off");
  std::printf("%-6s %6s %5s %-17s %5s %5s %6s %6s %9s %8s %9s %9s %12s %8s %4s %s\n", "scene", "tets", "r",
              "backend", "iters", "evals", "nwt/ev", "fac/ev", "wall s", "modes s", "fwd ms/it", "adj ms/it",
              "objective", "E error", "load", "status");
  std::vector<Row> rows;
  for (const Setting& setting : plan) {
    try {
      rows.push_back(run(settings, setting));
      print_row(rows.back());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "material_modes_bench: %s r=%s %s: %s\n", setting.scene.c_str(),
                   setting.modes ? std::to_string(*setting.modes).c_str() : "full",
                   to_string(setting.backend).c_str(), e.what());
      return 1;
    }
    // After every run, so that a long bench leaves its results so far.
    std::ofstream(settings.out) << dump_json(write_json(settings, rows), 2, true);
  }
  std::printf(
      "(wall = material modes + optimization; per-iteration times are totals / iterations; E error = "
      "volume-\n"
      " weighted relative L2 against the truth; capped = stopped by the iteration or time cap)\n");
  // Speed-up of each reduced setting over the full design of its scene, at its error ratio.
  for (const std::string& scene : settings.scenes) {
    const auto full = std::find_if(rows.begin(), rows.end(),
                                   [&](const Row& r) { return r.scene == scene && r.modes == "full"; });
    if (full == rows.end()) continue;
    // The full design may over-fit noisy data: its error can be lowest before it converges.
    double best = full->error, best_s = full->wall_s;
    for (std::size_t k = 0; k < full->history_error.size(); ++k)
      if (full->history_error[k] < best) {
        best = full->history_error[k];
        best_s = full->history_s[k];
      }
    std::printf("%-6s full design: final error %.4f after %.2f s, lowest %.4f after %.2f s\n", scene.c_str(),
                full->error, full->wall_s, best, best_s);
    for (const Row& r : rows) {
      if (r.scene != scene || r.modes == "full") continue;
      const double t_best = time_to_error(r, best);
      char reached_best[64] = "never";
      if (std::isfinite(t_best))
        std::snprintf(reached_best, sizeof reached_best, "after %.2f s (%.1fx sooner)", t_best,
                      best_s / t_best);
      const double t = time_to_error(r, full->error);
      char reached[96] = "never";
      if (std::isfinite(t))
        std::snprintf(reached, sizeof reached, "after %.2f s (%.1fx sooner)", t, full->wall_s / t);
      std::printf(
          "%-6s r=%-3s %-17s speed-up %7.1fx, error %.4f vs full %.4f (ratio %.3f); full's final error "
          "reached %s; its lowest %s\n",
          scene.c_str(), r.modes.c_str(), r.backend.c_str(), full->wall_s / r.wall_s, r.error, full->error,
          r.error / full->error, reached, reached_best);
    }
  }
  if (!bench::write_report(settings.out, write_json(settings, rows), "material_modes_bench")) return 1;
  for (const std::string& path : write_plots(settings, rows)) std::printf("wrote %s\n", path.c_str());
  return 0;
}

}  // namespace tailor::bench::material_modes_bench
