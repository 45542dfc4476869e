// The solver's defaults against the configuration before them, side by side in one run:
//   old  CHOLMOD's OpenMP loops at its compiled 4 threads, every Newton iteration and time
//        step factorizes (NewtonOptions::keep_constant_factorization = false, reuse_factorization
//        off);
//   new  the defaults: CHOLMOD's loops serialized (forward/solve/threads.hpp), the factor of a
//        constant Hessian kept across iterations, time steps and the adjoint, and Newton's kept
//        factor as CG preconditioner where it pays (FactorReuse::automatic).
// Figures (medians over repeats in this run):
//   factorization  one numeric factorization (and one back-solve) of the linear block's Hessian;
//   inverse        one forward solve + one gradient of a linear per-element inverse problem
//                  (design: log E per tet; objective: top-face target positions), at a new
//                  design each time, as an optimizer asks for them;
//   dynamics       one implicit Euler step of a linear cantilever (consistent mass, Rayleigh
//                  damping), as a ratio of one factorization + one back-solve of its matrix;
//   newton         a Neo-Hookean Newton iteration as a ratio of factorization + back-solve.
// The error these settings cost is reported with them: the largest relative difference of the
// equilibria, gradients and trajectories between old and new.
// Writes JSON (--out, default bench_solver_defaults.json) and prints a table.
//
// usage: solver_defaults_bench [--tets 6000,47000] [--steps 20] [--repeats 5] [--out FILE]
#include <cstdio>
#include <string>
#include <vector>

#include "adjoint/static_functional.hpp"
#include "bench_cli.hpp"
#include "cantilever.hpp"
#include "forward/dynamics/setup.hpp"
#include "forward/dynamics/time_integrator.hpp"
#include "forward/solve/threads.hpp"
#include "loaded_block.hpp"
#include "objectives/target_positions.hpp"

namespace tailor::bench::solver_defaults_bench {

using namespace tailor;
using bench::Clock;
using bench::Json;
using bench::median;
using bench::seconds_since;

namespace {

struct Config {
  const char* name;
  int factorization_threads;
  bool keep_constant;
  FactorReuse reuse;  // Newton's kept factor as CG preconditioner
};
constexpr Config kOld{"old", 0, false, FactorReuse::off};
constexpr Config kNew{"new", 1, true, FactorReuse::automatic};

void use(const Config& config) {
  ThreadSettings threads = thread_settings();
  threads.factorization = config.factorization_threads;
  set_thread_settings(threads);
}

// Median seconds of one factorization and of one back-solve of the block's linear Hessian.
std::pair<double, double> factor_and_solve(const SparseMatrix& upper, int repeats) {
  SparseCholesky cholesky;
  cholesky.analyze(upper);
  std::vector<double> factor, solve;
  const Vector rhs = Vector::Ones(upper.rows());
  for (int r = 0; r < repeats; ++r) {
    auto t0 = Clock::now();
    if (!cholesky.factorize(upper).positive_definite)
      throw std::runtime_error("bench matrix is not positive definite");
    factor.push_back(seconds_since(t0));
    t0 = Clock::now();
    const Vector x = cholesky.solve(rhs);
    solve.push_back(seconds_since(t0));
  }
  return {median(factor), median(solve)};
}

SparseMatrix rest_hessian(const Model& model, const Vector& y, const Vector& p) {
  ReducedAssembler assembler(model);
  SparseMatrix h = assembler.hessian_pattern_matrix();
  assembler.evaluate(y, p, nullptr, nullptr, &h, HessianMode::exact);
  return h;
}

struct InverseFigures {
  double forward_gradient = 0;  // median seconds of value + gradient at a new design
  double factorizations = 0;    // per evaluation
  Vector last_gradient;
};

InverseFigures inverse_problem(const bench::LoadedBlock& block, const Config& config, int repeats) {
  use(config);
  const int m = block.mesh.num_elements();
  Matrix targets(block.top_vertices.size(), 3);
  for (std::size_t k = 0; k < block.top_vertices.size(); ++k)
    targets.row(k) =
        block.mesh.rest_positions.row(block.top_vertices[k]) + Eigen::RowVector3d(0.02, 0.0, -0.03);
  StaticFunctionalOptions options;
  options.newton.keep_constant_factorization = config.keep_constant;
  options.newton.reuse_factorization = config.reuse;
  StaticFunctional f(*block.model, embed_blocks(block.parameters, {{0, exp_map(m)}}),
                     std::make_shared<TargetPositions>(3, block.top_vertices, targets), block.rest_unknowns(),
                     options);
  const Vector z0 = block.parameters.head(m).array().log().matrix();
  Vector g;
  f.value_and_gradient(z0, g);  // symbolic analysis and first touch, not timed
  InverseFigures out;
  std::vector<double> times;
  int factorizations = 0;
  for (int r = 1; r <= repeats; ++r) {
    const Vector z = z0.array() + 0.01 * r;  // a new design, as an optimizer step makes it
    const auto t0 = Clock::now();
    f.value_and_gradient(z, g);
    times.push_back(seconds_since(t0));
    factorizations +=
        f.last_newton().factorizations() + (f.last_hessian_solve() == HessianSolve::fresh_factorization);
  }
  out.forward_gradient = median(times);
  out.factorizations = static_cast<double>(factorizations) / repeats;
  out.last_gradient = g;
  return out;
}

struct DynamicsFigures {
  double step = 0;  // median seconds per step
  double factorizations_per_step = 0;
  double factor = 0, solve = 0;  // of the step matrix
  Vector final_state;
};

DynamicsFigures linear_dynamics(int target_tets, int steps, const Config& config, int repeats) {
  use(config);
  DynamicTerms terms;
  const bench::Cantilever bar = bench::make_cantilever(
      4.0, bench::cantilever_cells(target_tets, 4.0), MaterialKind::linear,
      [&](Model& model, const Mesh& mesh) {
        terms = add_dynamics_terms(
            model, mesh, DynamicsSetup{MassLumping::consistent, Eigen::Vector3d(0, 0, -9.81), true});
      });
  const int m = bar.mesh.num_elements();
  Vector p = bench::cantilever_parameters(bar, 1e6, 0.3);
  p.segment(terms.density_offset, m).setConstant(1000.0);
  p[terms.alpha_offset] = 0.5;
  p[terms.beta_offset] = 1e-3;
  TimeIntegratorOptions options;
  options.scheme = TimeScheme::implicit_euler;
  options.time_step = 0.01;
  options.newton.keep_constant_factorization = config.keep_constant;
  options.newton.reuse_factorization = config.reuse;
  TimeIntegrator integrator(*bar.model, options);
  DynamicState state = integrator.initial_state(bar.rest, Vector::Zero(bar.rest.size()), p);
  std::vector<double> times;
  int factorizations = 0;
  for (int s = 0; s < steps; ++s) {
    const auto t0 = Clock::now();
    const NewtonResult r = integrator.step(state, p);
    times.push_back(seconds_since(t0));
    if (!r.converged()) throw std::runtime_error("dynamics step failed: " + r.message);
    factorizations += r.factorizations();
  }
  DynamicsFigures out;
  out.step = median(times);
  out.factorizations_per_step = static_cast<double>(factorizations) / steps;
  integrator.configure_step(state, p);
  std::tie(out.factor, out.solve) = factor_and_solve(rest_hessian(*bar.model, state.y, p), repeats);
  out.final_state = state.x;
  return out;
}

// Mean seconds per Newton iteration of a Neo-Hookean solve from rest, and where they go.
struct NewtonFigures {
  double iteration = 0, assembly = 0, factorization = 0, solve = 0, line_search = 0;
  int iterations = 0, factorizations = 0;
};

NewtonFigures newton_iteration(const bench::LoadedBlock& block, const Config& config) {
  use(config);
  NewtonOptions options;
  options.reuse_factorization = config.reuse;
  NewtonSolver newton(*block.model, options);
  Vector y = block.rest_unknowns();
  const NewtonResult r = newton.solve(block.parameters, y);
  if (!r.converged()) throw std::runtime_error("Neo-Hookean solve failed: " + r.message);
  NewtonFigures f;
  f.iterations = std::max(1, r.iterations);
  f.iteration = (r.total_seconds - r.analysis_seconds) / f.iterations;
  for (const NewtonIteration& it : r.history) {
    f.assembly += it.assembly_seconds / f.iterations;
    f.factorization += it.factorization_seconds / f.iterations;
    f.solve += it.solve_seconds / f.iterations;
    f.line_search += it.line_search_seconds / f.iterations;
  }
  f.factorizations = r.factorizations();
  return f;
}

}  // namespace

int run(int argc, char** argv) {
  std::vector<int> sizes{6000, 47000};
  int steps = 20, repeats = 5;
  std::string out = "bench_solver_defaults.json";
  bench::Cli cli("solver_defaults_bench", "The solver's defaults against the configuration before them.");
  cli.tets(sizes, 24);  // the dynamics figure's cantilever needs 24
  cli.steps(steps, "implicit Euler steps of the dynamics figure");
  cli.repeats(repeats);
  cli.out(out);
  if (const auto exit = cli.parse(argc, argv)) return *exit;
  Json report = bench::report("solver_defaults");
  Json rows = Json::array();
  std::printf("%7s | %-6s %9s %9s | %11s %7s | %9s %7s %7s | %8s\n", "tets", "config", "factor s", "solve s",
              "fwd+grad s", "facts", "step s", "facts", "/(f+s)", "newton/(f+s)");
  for (int target : sizes) {
    const bench::LoadedBlock linear = bench::make_loaded_block(target, MaterialKind::linear);
    const bench::LoadedBlock neo = bench::make_loaded_block(target, MaterialKind::neo_hookean);
    const SparseMatrix h = rest_hessian(*linear.model, linear.rest_unknowns(), linear.parameters);
    Vector gradient[2], trajectory[2];
    for (const Config* config : {&kOld, &kNew}) {
      use(*config);
      const auto [factor, solve] = factor_and_solve(h, repeats);
      const InverseFigures inverse = inverse_problem(linear, *config, repeats);
      const DynamicsFigures dynamics = linear_dynamics(target, steps, *config, repeats);
      use(*config);
      const NewtonFigures newton = newton_iteration(neo, *config);
      const double iteration = newton.iteration;
      const int k = config == &kNew;
      gradient[k] = inverse.last_gradient;
      trajectory[k] = dynamics.final_state;
      const double dynamics_ratio = dynamics.step / (dynamics.factor + dynamics.solve);
      const double newton_ratio = iteration / (factor + solve);
      std::printf("%7d | %-6s %9.4f %9.4f | %11.4f %7.1f | %9.4f %7.2f %7.2f | %8.2f\n",
                  linear.mesh.num_elements(), config->name, factor, solve, inverse.forward_gradient,
                  inverse.factorizations, dynamics.step, dynamics.factorizations_per_step, dynamics_ratio,
                  newton_ratio);
      std::printf(
          "%7s   Neo-Hookean Newton: %d iterations, %d factorizations; per iteration %.4f s = assembly %.4f "
          "+ "
          "factorization %.4f + solve %.4f + line search %.4f (+ rest)\n",
          "", newton.iterations, newton.factorizations, newton.iteration, newton.assembly,
          newton.factorization, newton.solve, newton.line_search);
      rows.push_back({{"tets", linear.mesh.num_elements()},
                      {"config", config->name},
                      {"factorization_seconds", factor},
                      {"solve_seconds", solve},
                      {"inverse_forward_gradient_seconds", inverse.forward_gradient},
                      {"inverse_factorizations_per_evaluation", inverse.factorizations},
                      {"dynamics_step_seconds", dynamics.step},
                      {"dynamics_factorizations_per_step", dynamics.factorizations_per_step},
                      {"dynamics_step_over_factor_and_solve", dynamics_ratio},
                      {"newton_iteration_seconds", iteration},
                      {"newton_iteration_over_factor_and_solve", newton_ratio},
                      {"newton_iterations", newton.iterations},
                      {"newton_factorizations", newton.factorizations},
                      {"newton_seconds_per_iteration",
                       {{"assembly", newton.assembly},
                        {"factorization", newton.factorization},
                        {"solve", newton.solve},
                        {"line_search", newton.line_search}}}});
    }
    const double gradient_difference = (gradient[1] - gradient[0]).norm() / gradient[0].norm();
    const double trajectory_difference =
        (trajectory[1] - trajectory[0]).norm() / (trajectory[0] - linear.rest).norm();
    std::printf("%7s   error of new vs old: gradient %.2e, final dynamics state %.2e (relative)\n", "",
                gradient_difference, trajectory_difference);
    rows.back()["gradient_difference_to_old"] = gradient_difference;
    rows.back()["trajectory_difference_to_old"] = trajectory_difference;
  }
  report["rows"] = rows;
  return bench::write_report(out, report, "solver_defaults_bench") ? 0 : 1;
}

}  // namespace tailor::bench::solver_defaults_bench
