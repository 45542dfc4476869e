#include "problems/fem/commands.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include "forward/core/timing.hpp"
#include "problems/output_process.hpp"

namespace tailor {
namespace {

void print_setup(std::ostream& log, const Scene& scene, const StaticSetup& setup) {
  log << "scene '" << scene.name << "' (" << scene.source << "): " << setup.dim() << "D mesh, "
      << setup.mesh.num_vertices() << " vertices, " << setup.mesh.num_elements()
      << (setup.quadratic ? " quadratic elements (" + std::to_string(setup.num_nodes()) + " nodes), " : " elements, ")
      << setup.materials.size() << " material(s); " << setup.num_dofs() << " DOFs, "
      << setup.fixed_dofs.size() << " fixed" << (setup.has_loads ? "" : "; no loads") << "\n";
}

void print_summary(std::ostream& log, const SimulateRun& run) {
  const StaticSolution& s = run.solution;
  const RunTimings& t = run.timings;
  int iterations = 0;
  for (const LoadStep& step : s.steps) iterations += step.newton.iterations;
  const NewtonResult& last = s.steps.back().newton;
  log << std::defaultfloat << std::setprecision(4)
      << (s.converged ? "converged" : "FAILED (" + s.status + ")") << " after " << iterations
      << " Newton iterations in " << s.steps.size() << " load step(s): " << s.message << "; residual "
      << std::scientific << std::setprecision(3) << last.final_residual << ", energy " << s.energy
      << ", max displacement " << s.max_displacement << " at vertex " << s.max_displacement_vertex << "\n";
  log << std::fixed << std::setprecision(3) << "time " << t.total << " s: setup " << t.setup << ", analysis "
      << t.analysis << ", assembly " << t.assembly << ", factorization " << t.factorization << ", solve "
      << t.solve << ", line search " << t.line_search << ", output " << t.output << "\n"
      << std::defaultfloat;
}

// Checks one override against the mesh and its open range (lower, upper), and that no element
// of a spline material gets one; then replaces the setup's values.
void apply_override(const Scene& scene, StaticSetup& setup, const Eigen::VectorXd& values, const char* name,
                    double lower, double upper, Eigen::VectorXd& target) {
  if (values.size() == 0) return;
  const Eigen::Index ne = setup.mesh.num_elements();
  const std::string what = scene.source + ": " + name;
  if (values.size() != ne)
    throw std::invalid_argument(what + " has " + std::to_string(values.size()) + " values, the mesh has " +
                                std::to_string(ne) + " elements (one value per element)");
  for (Eigen::Index e = 0; e < ne; ++e) {
    const double v = values[e];
    if (!(std::isfinite(v) && v > lower && v < upper)) {
      std::ostringstream message;
      message << what << "[" << e << "] = " << v << ": expected a finite number > " << lower;
      if (std::isfinite(upper)) message << " and < " << upper;
      throw std::invalid_argument(message.str());
    }
  }
  for (Eigen::Index e = 0; e < ne; ++e) {
    const MaterialBlock& block = setup.materials[static_cast<std::size_t>(setup.element_material[e])];
    if (block.spline_curves)
      throw std::invalid_argument(what + ": element " + std::to_string(e) + " is of " +
                                  scene.materials[static_cast<std::size_t>(setup.element_material[e])].key +
                                  ", a spline material, whose energy has no " + name + " to replace");
  }
  target = values;
}

}  // namespace

SimulateRun simulate_scene(const Scene& scene, const std::string& out_dir, std::ostream* log) {
  return simulate_scene(scene, MaterialOverrides{}, out_dir, log);
}

SimulateRun simulate_scene(const Scene& scene, const MaterialOverrides& overrides, const std::string& out_dir,
                           std::ostream* log) {
  const auto t_start = Clock::now();
  SimulateRun run;
  run.setup = setup_static_scene(scene);
  apply_override(scene, run.setup, overrides.youngs_modulus, "youngs_modulus", 0.0,
                 std::numeric_limits<double>::infinity(), run.setup.youngs_modulus);
  apply_override(scene, run.setup, overrides.poisson_ratio, "poisson_ratio", -1.0, 0.5,
                 run.setup.poisson_ratio);
  require_supported(scene, run.setup);
  run.timings.setup = seconds_since(t_start);
  if (log) print_setup(*log, scene, run.setup);

  run.solution = solve_static(run.setup, log);
  const StaticSolution& s = run.solution;
  run.timings.setup += s.model_seconds;
  run.timings.analysis = s.analysis_seconds;
  run.timings.assembly = s.assembly_seconds;
  run.timings.factorization = s.factorization_seconds;
  run.timings.solve = s.solve_seconds;
  run.timings.line_search = s.line_search_seconds;

  const auto t_output = Clock::now();
  std::error_code error;
  // Only the process that writes files (rank 0 of a replicated MPI run) creates and fills them.
  if (writes_output()) std::filesystem::create_directories(out_dir, error);
  if (error)
    throw std::runtime_error("cannot create the output folder '" + out_dir + "': " + error.message());
  run.report_path = (std::filesystem::path(out_dir) / "report.json").string();
  run.result_path = (std::filesystem::path(out_dir) / "result.vtu").string();
  if (writes_output()) write_result_vtu(run.result_path, run.setup, run.solution);
  run.timings.output = seconds_since(t_output);
  run.timings.total = seconds_since(t_start);
  if (writes_output()) write_report_json(run.report_path, scene, run.setup, run.solution, run.timings);
  if (log) {
    print_summary(*log, run);
    *log << "wrote " << run.report_path << " and " << run.result_path << "\n";
  }
  return run;
}

bool check_scene(const Scene& scene, unsigned seed, std::ostream* log) {
  const StaticSetup setup = setup_static_scene(scene);
  if (log)
    *log << "derivative checks of scene '" << scene.name << "' (" << scene.source
         << ") at a perturbed state, seed " << seed << "\n";
  int failed = 0;
  const std::vector<EnergyTermCheck> checks = check_static_scene(setup, seed);
  for (const EnergyTermCheck& check : checks) {
    if (log) *log << check.table();
    if (check_failed(check)) ++failed;
  }
  if (log)
    *log << checks.size() << " energy term(s) checked: "
         << (failed ? std::to_string(failed) + " FAILED" : std::string("all passed")) << "\n";
  return failed == 0;
}

}  // namespace tailor
