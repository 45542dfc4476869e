// Per-element modulus recovery, the workload the optimizer back-ends are chosen for: the loaded
// unit block of bench/loaded_block.hpp (linear material, about 6k or 48k tets), one log E per
// tet, observed positions at every free vertex (synthesised from a smooth true field, no noise),
// a smoothness regularizer on log E, bounds 1e4 <= E <= 1e8, starting from E = 2e6 everywhere.
// Every back-end minimizes the same functional from the same start; the figure is the time each
// needs to reach within 1e-3 (relative) of the best objective any of them found, with the
// factorizations, back-solves and curvature products spent until then. newton_cg runs twice:
// with its default curvature (Gauss-Newton products: the objective is least squares) and with
// exact Hessian-vector products.
//
// --per-iteration prints each iteration's factorizations, back-solves and products;
// --cg-resolution sets newton_cg's OptimizerOptions::cg_objective_resolution (0: its CG stops on
// the residual test alone, as before that rule).
//
// --reuse chooses how the forward solves use the kept factorization (NewtonOptions): auto (the
// default rule), across (the rule before: CG preconditioned by the previous design's factor),
// off (factorize every new design).
// Writes JSON (--out, default bench_recovery.json) and prints a table.
//
// usage: recovery_bench [--size 6k|48k] [--backends a,b] [--reuse auto|across|off]
//                       [--exact-hessian yes|no] [--jacobi yes|no] [--per-iteration yes|no]
//                       [--cg-resolution X] [--max-iterations N] [--time-limit S] [--out FILE]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "adjoint/static_functional.hpp"
#include "bench_cli.hpp"
#include "loaded_block.hpp"
#include "objectives/material_smoothness.hpp"
#include "objectives/target_positions.hpp"
#include "objectives/weighted_sum.hpp"
#include "optimizers/backend_registry.hpp"
#include "optimizers/checkpoint.hpp"

namespace tailor::bench::recovery_bench {

using namespace tailor;
using bench::Json;

namespace {

constexpr double kTarget = 1e-3;  // relative distance to the best objective

// One optimizer run: the back-end, and for newton_cg its curvature.
struct Variant {
  OptimizerBackend backend;
  CurvatureProducts curvature = CurvatureProducts::automatic;
  bool precondition = false;  // newton_cg: CG preconditioned by the Gauss-Newton diagonal
  std::string label() const {
    return to_string(backend) + (curvature == CurvatureProducts::exact ? " (exact Hessian)" : "") +
           (precondition ? " (Jacobi CG)" : "");
  }
};

// The state after an iteration (from the checkpoint handed out after each).
struct Sample {
  int iteration = 0;
  double seconds = 0.0, objective = 0.0;
  FunctionalCounters counters;
};

struct Run {
  Variant variant;
  OptimizerResult result;
  std::vector<Sample> samples;  // row 0 and every iteration
  double evaluation_seconds = 0.0;  // forward + adjoint seconds per evaluation
};

constexpr double kPi = 3.14159265358979323846;

// log E of the true field at an element centroid c: smooth, a factor of about 5 between its
// extremes, mean about log 1e6.
double true_log_modulus(const Eigen::Vector3d& c) {
  return std::log(1e6) + 0.6 * std::sin(2.0 * kPi * c.x()) * std::cos(kPi * c.y()) + 0.4 * c.z() - 0.2;
}

// Built in place (the model refers to the block's mesh).
struct Recovery {
  bench::LoadedBlock block;
  ObjectivePtr objective;
  Vector z0, truth;
  Bounds bounds;

  explicit Recovery(int target_tets) : block(bench::make_loaded_block(target_tets, MaterialKind::linear)) {
    const Mesh& mesh = block.mesh;
    const int m = mesh.num_elements();
    truth.resize(m);
    for (int e = 0; e < m; ++e) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int a = 0; a < 4; ++a) c += 0.25 * mesh.rest_positions.row(mesh.elements(e, a)).transpose();
      truth[e] = true_log_modulus(c);
    }
    // Observations: the equilibrium under the true field, at every vertex not held by the base.
    Vector p = block.parameters;
    p.head(m) = truth.array().exp().matrix();
    NewtonSolver newton(*block.model);
    Vector y = block.rest_unknowns();
    if (!newton.solve(p, y).converged()) throw std::runtime_error("recovery_bench: the true equilibrium failed");
    const Vector x = block.model->elimination().expand(y);
    std::vector<int> observed;
    for (int v = 0; v < mesh.num_vertices(); ++v)
      if (mesh.rest_positions(v, 2) > 1e-9) observed.push_back(v);
    Matrix targets(observed.size(), 3);
    double displacement = 0.0;
    for (std::size_t k = 0; k < observed.size(); ++k) {
      targets.row(k) = x.segment<3>(3 * observed[k]).transpose();
      displacement += (x.segment<3>(3 * observed[k]) - block.rest.segment<3>(3 * observed[k])).squaredNorm();
    }
    // The data term relative to the observed displacements (1 = the misfit of the rest state),
    // and a weak smoothness term on log E.
    const auto data = std::make_shared<TargetPositions>(3, observed, targets);
    const auto smooth = std::make_shared<MaterialSmoothness>(
        mesh, 0, 1.0, MaterialSmoothnessOptions{AdjacencyWeighting::unit, true});
    objective = std::make_shared<WeightedSum>(std::vector<ObjectivePtr>{data, smooth},
                                              std::vector<double>{1.0 / displacement, 1e-4 / m});
    z0 = Vector::Constant(m, std::log(2e6));
    bounds = {Vector::Constant(m, std::log(1e4)), Vector::Constant(m, std::log(1e8))};
  }
};

Run run_variant(const Recovery& recovery, const Variant& variant, const std::string& reuse, int max_iterations,
                double time_limit, double gradient_tolerance, double cg_resolution) {
  const int m = recovery.block.mesh.num_elements();
  StaticFunctionalOptions options;
  options.newton.reuse_factorization = reuse == "off" ? FactorReuse::off : FactorReuse::automatic;
  options.newton.reuse_across_parameters = reuse == "across";
  StaticFunctional functional(*recovery.block.model, embed_blocks(recovery.block.parameters, {{0, exp_map(m)}}),
                              recovery.objective, recovery.block.rest_unknowns(), options);
  Run run;
  run.variant = variant;
  OptimizerOptions o;
  o.backend = variant.backend;
  o.curvature = variant.curvature;
  o.precondition_curvature = variant.precondition;
  o.cg_objective_resolution = cg_resolution;
  o.max_iterations = max_iterations;
  o.time_limit_seconds = time_limit;
  o.gradient_tolerance = gradient_tolerance;
  o.checkpoint_every = 1;
  o.on_checkpoint = [&run](const OptimizerCheckpoint& c) {
    run.samples.push_back({c.iteration, c.seconds, c.objective, c.counters});
  };
  const bool bounded = find_backend(variant.backend).capabilities.bounds;
  run.result = minimize(functional, recovery.z0, bounded ? recovery.bounds : Bounds{}, {}, o);
  const FunctionalCounters& c = run.result.counters;
  run.evaluation_seconds = c.evaluations > 0 ? (c.forward_seconds + c.adjoint_seconds) / c.evaluations : 0.0;
  return run;
}

// The first sample within kTarget of `best`, or null.
const Sample* time_to_target(const Run& run, double best) {
  for (const Sample& s : run.samples)
    if (s.objective <= best + kTarget * std::abs(best)) return &s;
  return nullptr;
}

// Each iteration's work (the difference of the counters between checkpoints): where a
// back-end's products and factorizations go.
void print_iterations(const Run& run) {
  std::printf("    %5s %16s %9s %8s %11s %9s\n", "iter", "objective", "s", "factors", "back-solves", "products");
  for (std::size_t k = 0; k < run.samples.size(); ++k) {
    const Sample& s = run.samples[k];
    const FunctionalCounters before = k > 0 ? run.samples[k - 1].counters : FunctionalCounters{};
    const double seconds = s.seconds - (k > 0 ? run.samples[k - 1].seconds : 0.0);
    std::printf("    %5d %16.9e %9.3f %8ld %11ld %9d\n", s.iteration, s.objective, seconds,
                s.counters.factorizations - before.factorizations, s.counters.back_solves - before.back_solves,
                s.counters.hessian_vectors - before.hessian_vectors);
  }
}

}  // namespace

int run(int argc, char** argv) {
  std::string size = "6k", reuse = "auto", exact = "yes", jacobi = "no", per_iteration = "no",
              out = "bench_recovery.json";
  int max_iterations = 500;
  double time_limit = 120.0;
  double cg_resolution = OptimizerOptions{}.cg_objective_resolution;
  // Back-ends whose work is dense in the number of design variables (SLSQP's quasi-Newton
  // matrix, Ceres' Levenberg-Marquardt Jacobian) are left out by default.
  std::vector<std::string> backends{"newton_cg", "nlopt_lbfgs", "ipopt", "ceres_lbfgs", "nlopt_mma",
                                    "gradient_descent"};
  bench::Cli cli("recovery_bench", "Per-element modulus recovery with every optimizer back-end.");
  cli.choice("--size", size, "mesh: about 6k or 48k tets", {"6k", "48k"});
  cli.names("--backends", backends, "back-ends to run (newton_cg runs with Gauss-Newton and exact products)",
            "NAME", [](const std::string& name) {
              try {
                parse_optimizer_backend(name);
                return std::string();
              } catch (const std::invalid_argument& e) {
                return std::string(e.what());
              }
            });
  cli.choice("--reuse", reuse, "factor reuse of the forward solves: auto, across (the rule before), off",
             {"auto", "across", "off"});
  cli.choice("--exact-hessian", exact, "also run newton_cg with exact Hessian-vector products", {"yes", "no"});
  cli.choice("--jacobi", jacobi, "also run newton_cg with its CG preconditioned by the Gauss-Newton diagonal",
             {"yes", "no"});
  cli.choice("--per-iteration", per_iteration,
             "print each back-end's work per iteration (objective, seconds, factorizations, back-solves, products)",
             {"yes", "no"});
  cli.integer("--max-iterations", max_iterations, "iterations per back-end", 1);
  cli.number("--time-limit", time_limit, "seconds per back-end", 0.0);
  cli.number("--cg-resolution", cg_resolution,
             "newton_cg (Gauss-Newton): CG stops once the model resolves the objective to this (0 = residual test only)",
             0.0, true);
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;

  const Recovery recovery(size == "6k" ? 6000 : 48000);
  const int m = recovery.block.mesh.num_elements();
  std::printf("recovery: %d tets, %d design variables, reuse %s\n", m, m, reuse.c_str());
  // One gradient tolerance for all: 1e-8 of the starting gradient (infinity norm), tight enough
  // that the back-ends' own tests do not stop them before the target.
  double tolerance = 0.0;
  {
    StaticFunctional f(*recovery.block.model, embed_blocks(recovery.block.parameters, {{0, exp_map(m)}}),
                       recovery.objective, recovery.block.rest_unknowns());
    Vector g;
    f.value_and_gradient(recovery.z0, g);
    tolerance = 1e-8 * g.lpNorm<Eigen::Infinity>();
  }
  std::vector<Variant> variants;
  for (const std::string& name : backends) {
    const OptimizerBackend backend = parse_optimizer_backend(name);
    variants.push_back({backend});
    if (backend == OptimizerBackend::newton_cg && jacobi == "yes")
      variants.push_back({backend, CurvatureProducts::automatic, true});
    if (backend == OptimizerBackend::newton_cg && exact == "yes") variants.push_back({backend, CurvatureProducts::exact});
  }
  std::vector<Run> runs;
  double best = std::numeric_limits<double>::infinity();
  for (const Variant& v : variants) {
    runs.push_back(run_variant(recovery, v, reuse, max_iterations, time_limit, tolerance, cg_resolution));
    const Run& r = runs.back();
    std::printf("  %-28s %-14s %4d iterations  %8.3f s  objective %.9e\n", v.label().c_str(),
                to_string(r.result.status).c_str(), r.result.history.empty() ? 0 : r.result.history.back().iteration,
                r.result.seconds, r.result.objective);
    if (per_iteration == "yes") print_iterations(r);
    std::fflush(stdout);
    if (std::isfinite(r.result.objective)) best = std::min(best, r.result.objective);
  }

  std::printf("\nbest objective %.9e; time to within %.0e of it (relative):\n", best, kTarget);
  std::printf("%-28s | %9s %6s %8s %10s %8s | %9s %8s %8s %9s | %s\n", "back-end", "to target", "iters", "factors",
              "back-solves", "products", "total s", "iters", "factors", "s / eval", "error in E");
  Json report = bench::report("recovery");
  report["tets"] = m;
  report["reuse"] = reuse;
  report["cg_objective_resolution"] = cg_resolution;
  report["gradient_tolerance"] = tolerance;
  report["best_objective"] = best;
  report["target_relative"] = kTarget;
  Json rows = Json::array();
  const Run* lbfgs = nullptr;
  const Run* newton_cg = nullptr;
  for (const Run& r : runs) {
    const Sample* hit = time_to_target(r, best);
    const FunctionalCounters& c = r.result.counters;
    const Vector E = r.result.z.array().exp().matrix(), truth = recovery.truth.array().exp().matrix();
    const double error = ((E - truth).array() / truth.array()).abs().maxCoeff();
    const int iterations = r.result.history.empty() ? 0 : r.result.history.back().iteration;
    if (hit)
      std::printf("%-28s | %9.3f %6d %8ld %10ld %8d |", r.variant.label().c_str(), hit->seconds, hit->iteration,
                  hit->counters.factorizations, hit->counters.back_solves, hit->counters.hessian_vectors);
    else
      std::printf("%-28s | %9s %6s %8s %10s %8s |", r.variant.label().c_str(), "-", "-", "-", "-", "-");
    std::printf(" %9.3f %8d %8ld %9.4f | %.2e\n", r.result.seconds, iterations, c.factorizations,
                r.evaluation_seconds, error);
    if (r.variant.backend == OptimizerBackend::nlopt_lbfgs) lbfgs = &r;
    if (r.variant.backend == OptimizerBackend::newton_cg && r.variant.curvature == CurvatureProducts::automatic &&
        !r.variant.precondition)
      newton_cg = &r;
    Json row = {{"backend", to_string(r.variant.backend)},
                {"curvature", to_string(r.variant.curvature)},
                {"preconditioned", r.variant.precondition},
                {"status", to_string(r.result.status)},
                {"message", r.result.message},
                {"iterations", iterations},
                {"objective", r.result.objective},
                {"seconds", r.result.seconds},
                {"evaluations", r.result.evaluations},
                {"factorizations", c.factorizations},
                {"back_solves", c.back_solves},
                {"hessian_vectors", c.hessian_vectors},
                {"forward_seconds", c.forward_seconds},
                {"adjoint_seconds", c.adjoint_seconds},
                {"forward_plus_adjoint_seconds_per_evaluation", r.evaluation_seconds},
                {"max_relative_error_in_E", error}};
    if (hit)
      row["to_target"] = {{"seconds", hit->seconds},
                          {"iterations", hit->iteration},
                          {"factorizations", hit->counters.factorizations},
                          {"back_solves", hit->counters.back_solves},
                          {"hessian_vectors", hit->counters.hessian_vectors}};
    rows.push_back(row);
  }
  if (lbfgs && newton_cg) {
    // Where L-BFGS stops (its own tests may stop it short of the target): newton_cg's time to
    // reach L-BFGS's final objective against L-BFGS's whole run.
    const double lbfgs_final = lbfgs->result.objective;
    const Sample* a = nullptr;
    for (const Sample& s : newton_cg->samples)
      if (s.objective <= lbfgs_final) {
        a = &s;
        break;
      }
    if (a) {
      std::printf("newton_cg reaches nlopt_lbfgs's final objective %.6e in %.3f s (%d iterations, %ld "
                  "factorizations); nlopt_lbfgs took %.3f s (%ld factorizations): ratio %.3f\n",
                  lbfgs_final, a->seconds, a->iteration, a->counters.factorizations, lbfgs->result.seconds,
                  lbfgs->result.counters.factorizations, a->seconds / lbfgs->result.seconds);
      report["newton_cg_to_lbfgs_final"] = {{"seconds", a->seconds},
                                            {"iterations", a->iteration},
                                            {"factorizations", a->counters.factorizations},
                                            {"lbfgs_seconds", lbfgs->result.seconds},
                                            {"ratio", a->seconds / lbfgs->result.seconds}};
    }
  }
  report["rows"] = rows;
  return bench::write_report(out, report, "recovery_bench") ? 0 : 1;
}

}  // namespace tailor::bench::recovery_bench
