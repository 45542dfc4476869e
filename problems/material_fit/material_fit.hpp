#pragma once
// Material fitting with principal-stretch spline curves (Xu, Sin, Zhu, Barbic 2015, section 6:
// fitting to force-displacement data): choose the control values of f, g, h so that the
// reaction forces of a set of load cases match targets, through the static adjoint.
// Targets come from a reference material (a closed-form material or a spline preset, solved on
// the same load cases) or are given as force curves (design).
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "forward/fem/material.hpp"
#include "optimizers/optimizer.hpp"
#include "problems/material_fit/load_cases.hpp"
#include "problems/material_fit/shape_constraints.hpp"

namespace tailor {

struct MaterialFitSpec {
  std::string name;
  std::string source;  // the scene file as given (for the report)
  int cells = 2;       // of the unit-cube specimen, per edge (shear needs >= 2)
  PrincipalStretchGrids grids;
  std::vector<LoadCase> cases;

  // Targets: exactly one of reference_material, reference_preset, target_forces.
  std::optional<MaterialKind> reference_material;  // closed form, with reference_lame
  std::optional<SplinePreset> reference_preset;    // spline preset on `grids`, with reference_lame
  LameParameters reference_lame{0.0, 0.0};
  std::vector<std::vector<double>> target_forces;  // per case, per amplitude

  // Start: a preset with these Lame parameters.
  SplinePreset initial_preset = SplinePreset::corotated;
  LameParameters initial_lame{0.0, 0.0};

  double smoothness = 0.0;              // alpha of the curve smoothness term
  std::vector<ShapeConstraint> shapes;  // e.g. convex f, h decreasing for J < 1
  OptimizerOptions optimizer;
};

// Wall-clock seconds of the parts of a fit.
struct MaterialFitTimings {
  double total = 0.0;         // the whole fit, up to (not including) writing report.json
  double setup = 0.0;         // specimen, targets (reference solves) and the functional
  double optimization = 0.0;  // initial forces and the optimizer, final forces and errors
  double forward = 0.0;       // Newton solves inside the optimization
  double adjoint = 0.0;       // adjoint solves inside the optimization
  double output = 0.0;        // plots and material.json
};

struct MaterialFitRun {
  OptimizerResult result;
  std::vector<std::vector<double>> target, initial, fitted;  // forces per case, per amplitude
  double relative_force_error = 0.0;                         // RMS(fitted - target) / RMS(target)
  double initial_relative_force_error = 0.0;
  // Only with a reference preset: RMS of dPsi/dl_a (fitted - reference) over stretch triples
  // sampled in the data range, relative to the RMS of the reference.
  std::optional<double> relative_stress_error;
  int evaluations = 0, forward_solves = 0, adjoint_solves = 0;
  MaterialFitTimings timings;
  std::string report_path;
  std::string material_path;  // DIR/material.json: the fitted curves, for "curves": {"file": ...}
};

// Solves the targets, fits, writes DIR/report.json, DIR/material.json and DIR/force_<case>.png. Throws
// std::invalid_argument on inconsistent specs and std::runtime_error when it cannot write.
MaterialFitRun run_material_fit(const MaterialFitSpec& spec, const std::string& out_dir, std::ostream* log,
                                std::ostream* progress);

// The convexity constraints (second differences of the controls >= 0) of the named curves over
// their whole range (shape_constraints with CurveShape::convex).
std::vector<Constraint> convexity_constraints(const PrincipalStretchCurves& knots,
                                              const std::vector<std::string>& curves);

}  // namespace tailor
