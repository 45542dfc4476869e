#include "problems/material_fit/material_fit.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <stdexcept>

#include "forward/fem/elastic_term.hpp"
#include "forward/fem/materials/spline_material.hpp"
#include "forward/solve/newton.hpp"
#include "problems/fem/spline_curves_json.hpp"
#include "problems/material_fit/curve_fit_functional.hpp"
#include "problems/material_fit/material_fit_report.hpp"
#include "problems/plot/line_plot.hpp"

namespace tailor {
namespace {

// Reaction forces of every case and step for the given term factory (solving each step,
// warm-started along the case).
template <class MakeStep>
std::vector<std::vector<double>> solve_forces(const MaterialFitSpec& spec, const Vector& p,
                                              MakeStep make_step) {
  std::vector<std::vector<double>> forces;
  for (const LoadCase& c : spec.cases) {
    forces.emplace_back();
    for (int s = 0; s < static_cast<int>(c.amplitudes.size()); ++s) {
      const SpecimenStep step = make_step(c, s);
      NewtonOptions options;
      options.relative_tolerance = 1e-11;
      NewtonSolver newton(*step.model, options);
      Vector y = step.rest_y;
      const NewtonResult r = newton.solve(p, y);
      if (!r.converged())
        throw std::runtime_error("load case '" + c.name + "', step " + std::to_string(s) +
                                 ": the reference solve did not converge (" + r.message + ")");
      forces.back().push_back(measured_force(step, step.model->elimination().expand(y), p));
    }
  }
  return forces;
}

double rms(const std::vector<std::vector<double>>& a, const std::vector<std::vector<double>>* minus) {
  double sum = 0.0;
  int n = 0;
  for (std::size_t c = 0; c < a.size(); ++c)
    for (std::size_t s = 0; s < a[c].size(); ++s, ++n) {
      const double d = a[c][s] - (minus ? (*minus)[c][s] : 0.0);
      sum += d * d;
    }
  return n ? std::sqrt(sum / n) : 0.0;
}

// RMS over sampled stretch triples of dPsi/dl (fitted - reference) / RMS(reference).
double stress_error(const PrincipalStretchCurves& fitted, const PrincipalStretchCurves& reference, double lo,
                    double hi) {
  double num = 0.0, den = 0.0;
  const int n = 7;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
        F(0, 0) = lo + (hi - lo) * i / (n - 1);
        F(1, 1) = lo + (hi - lo) * j / (n - 1);
        F(2, 2) = lo + (hi - lo) * k / (n - 1);
        MaterialEvaluation<3> a, b;
        evaluate_spline_material<3>(fitted, F, true, false, HessianMode::exact, a);
        evaluate_spline_material<3>(reference, F, true, false, HessianMode::exact, b);
        num += (a.stress - b.stress).squaredNorm();
        den += b.stress.squaredNorm();
      }
  return std::sqrt(num / den);
}

void plot_case(const std::string& path, const LoadCase& c, const std::vector<double>& target,
               const std::vector<double>& initial, const std::vector<double>& fitted, bool design) {
  LinePlot plot;
  plot.title = "load case " + c.name + " (" + to_string(c.kind) + ")";
  plot.x_label = c.kind == LoadCaseKind::shear ? "shear displacement" : "stretch";
  plot.y_label = "reaction force";
  plot.series.push_back({design ? "designed (target)" : "target", {30, 30, 30}, c.amplitudes, target});
  plot.series.push_back({"initial", {120, 160, 220}, c.amplitudes, initial});
  plot.series.push_back({design ? "achieved" : "fitted", {220, 60, 40}, c.amplitudes, fitted});
  write_line_plot_png(path, plot);
}

}  // namespace

std::vector<Constraint> convexity_constraints(const PrincipalStretchCurves& knots,
                                              const std::vector<std::string>& curves) {
  std::vector<ShapeConstraint> shapes;
  for (const std::string& curve : curves) shapes.push_back({curve, CurveShape::convex});
  return shape_constraints(knots, shapes);
}

MaterialFitRun run_material_fit(const MaterialFitSpec& spec, const std::string& out_dir, std::ostream* log,
                                std::ostream* progress) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto seconds_since = [](std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  };
  if (spec.cases.empty()) throw std::invalid_argument("material fit: no load cases");
  const Mesh mesh = load_case_mesh(spec.cells);
  const PrincipalStretchCurves knots = zero_curves(spec.grids);
  const bool design = !spec.target_forces.empty();
  MaterialFitRun run;

  // Targets.
  std::optional<PrincipalStretchCurves> reference_curves;
  if (design) {
    run.target = spec.target_forces;
  } else if (spec.reference_preset) {
    reference_curves = principal_stretch_preset(*spec.reference_preset, spec.reference_lame, spec.grids);
    run.target = solve_forces(spec, reference_curves->controls(),
                              [&](const LoadCase& c, int s) { return spline_load_step(mesh, c, s, knots); });
  } else if (spec.reference_material) {
    const int m = mesh.num_elements();
    Vector p(2 * m);
    const double mu = spec.reference_lame.mu, la = spec.reference_lame.lambda;
    p.head(m).setConstant(mu * (3 * la + 2 * mu) / (la + mu));  // Young's modulus from (lambda, mu)
    p.tail(m).setConstant(la / (2 * (la + mu)));
    const auto material = std::shared_ptr<const Material<3>>(make_material<3>(*spec.reference_material));
    run.target = solve_forces(spec, p, [&](const LoadCase& c, int s) {
      return load_step(mesh, c, s, std::make_unique<ElasticTerm<3>>(mesh, material, 0, m), 2 * m);
    });
  } else {
    throw std::invalid_argument("material fit: no targets (a reference material, preset or target forces)");
  }
  for (std::size_t c = 0; c < spec.cases.size(); ++c)
    if (run.target.at(c).size() != spec.cases[c].amplitudes.size())
      throw std::invalid_argument("material fit: load case '" + spec.cases[c].name + "' has " +
                                  std::to_string(spec.cases[c].amplitudes.size()) + " amplitudes but " +
                                  std::to_string(run.target[c].size()) + " target forces");

  std::vector<FitStep> steps;
  for (std::size_t c = 0; c < spec.cases.size(); ++c)
    for (std::size_t s = 0; s < spec.cases[c].amplitudes.size(); ++s)
      steps.push_back({static_cast<int>(c), static_cast<int>(s), run.target[c][s]});
  const double force_scale = std::max(rms(run.target, nullptr), 1e-12);
  CurveFitFunctional functional(mesh, spec.cases, steps, knots, force_scale, spec.smoothness);

  run.timings.setup = seconds_since(t0);
  const Vector z0 = principal_stretch_preset(spec.initial_preset, spec.initial_lame, spec.grids).controls();
  auto split = [&](const std::vector<double>& flat) {
    std::vector<std::vector<double>> out;
    std::size_t i = 0;
    for (const LoadCase& c : spec.cases) {
      out.emplace_back(flat.begin() + i, flat.begin() + i + c.amplitudes.size());
      i += c.amplitudes.size();
    }
    return out;
  };
  run.initial = split(functional.forces(z0));
  if (log)
    *log << "material fit '" << spec.name << "': " << spec.cases.size() << " load cases, " << steps.size()
         << " steps, " << z0.size() << " control values, " << mesh.num_elements() << " tets per specimen\n";
  const std::vector<Constraint> constraints = shape_constraints(knots, spec.shapes);
  OptimizerOptions options = spec.optimizer;
  options.progress = progress;
  run.result = minimize(functional, z0, Bounds{}, constraints, options);
  run.fitted = split(functional.forces(run.result.z));
  run.relative_force_error = rms(run.fitted, &run.target) / force_scale;
  run.initial_relative_force_error = rms(run.initial, &run.target) / force_scale;
  double lo = 1.0, hi = 1.0;
  for (const LoadCase& c : spec.cases)
    for (double a : c.amplitudes)
      if (c.kind != LoadCaseKind::shear) lo = std::min(lo, a), hi = std::max(hi, a);
  PrincipalStretchCurves fitted_curves = knots;
  fitted_curves.set_controls(run.result.z);
  if (reference_curves) run.relative_stress_error = stress_error(fitted_curves, *reference_curves, lo, hi);

  const double optimization_end = seconds_since(t0);
  run.timings.optimization = optimization_end - run.timings.setup;
  run.timings.forward = functional.counters().forward_seconds;
  run.timings.adjoint = functional.counters().adjoint_seconds;
  run.evaluations = run.result.evaluations;
  run.forward_solves = functional.counters().forward_solves;
  run.adjoint_solves = functional.counters().adjoint_solves;

  // Output.
  std::error_code error;
  std::filesystem::create_directories(out_dir, error);
  if (error)
    throw std::runtime_error("cannot create the output folder '" + out_dir + "': " + error.message());
  for (std::size_t c = 0; c < spec.cases.size(); ++c)
    plot_case((std::filesystem::path(out_dir) / force_plot_name(spec.cases[c])).string(), spec.cases[c],
              run.target[c], run.initial[c], run.fitted[c], design);
  // The fitted material in a form scenes reference: "curves": {"file": ".../material.json"}.
  run.material_path = (std::filesystem::path(out_dir) / "material.json").string();
  write_spline_material_file(run.material_path, fitted_curves, "material fit '" + spec.name + "'");
  run.timings.output = seconds_since(t0) - optimization_end;
  run.timings.total = seconds_since(t0);
  run.report_path = (std::filesystem::path(out_dir) / "report.json").string();
  write_material_fit_report(run.report_path, spec, run, fitted_curves, mesh);
  if (log) {
    *log << "status: " << to_string(run.result.status) << " (" << run.result.message << ")\n"
         << "relative force error: initial " << run.initial_relative_force_error << ", final "
         << run.relative_force_error << "\n";
    if (run.relative_stress_error)
      *log << "relative stress error vs the reference curves: " << *run.relative_stress_error << "\n";
    *log << "wrote " << run.report_path << ", " << run.material_path << " and the force plots\n";
  }
  return run;
}

}  // namespace tailor
