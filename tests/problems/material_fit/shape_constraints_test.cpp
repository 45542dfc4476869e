// Shape constraints on the spline curves: the control differences they bound are sufficient
// for the curve's shape (sampled slopes and curvatures of random admissible controls), they cut
// off curves of the wrong shape, and a fit under an active constraint returns curves that obey
// it (the Neo-Hookean volumetric curve h(J) = lambda'/2 (J - alpha)^2 + c decreases up to
// J = alpha > 1, principal_stretch_curves.hpp; asking for an increasing h on [0.6, 1.4] must bind).
#include "problems/material_fit/shape_constraints.hpp"

#include <gtest/gtest.h>

#include <random>

#include "problems/material_fit/material_fit.hpp"
#include "tests/support/temp_folder.hpp"

namespace tailor::shape_constraints_test {
namespace {

PrincipalStretchGrids coarse_grids() {
  PrincipalStretchGrids g;
  g.uniaxial = {0.5, 2.0, 5};
  g.biaxial = {0.25, 4.0, 5};
  g.volumetric = {0.2, 3.0, 7};
  return g;
}

// Smallest sampled slope (or curvature) of the volumetric curve of `z` on [lo, hi].
double min_sampled(const Vector& z, double lo, double hi, bool curvature) {
  PrincipalStretchCurves curves = zero_curves(coarse_grids());
  curves.set_controls(z);
  double smallest = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= 400; ++k) {
    const CubicSpline::Sample s = curves.volumetric.evaluate(lo + (hi - lo) * k / 400.0);
    smallest = std::min(smallest, curvature ? s.curvature : s.slope);
  }
  return smallest;
}

TEST(ShapeConstraints, DifferencesAreSufficientForTheShape) {
  const PrincipalStretchCurves knots = zero_curves(coarse_grids());  // volumetric: h = 0.4, 7 intervals
  const int offset = knots.uniaxial.num_controls() + knots.biaxial.num_controls();
  // [0.7, 1.5] meets intervals 1 .. 3 (knots 0.2, 0.6, 1.0, 1.4, 1.8): 5 first differences.
  const std::vector<Constraint> increasing =
      shape_constraints(knots, {{"volumetric", CurveShape::increasing, 0.7, 1.5}});
  EXPECT_EQ(increasing.size(), 5u);
  const std::vector<Constraint> convex =
      shape_constraints(knots, {{"volumetric", CurveShape::convex, 0.7, 1.5}});
  EXPECT_EQ(convex.size(), 4u);
  EXPECT_EQ(shape_constraints(knots, {{"volumetric", CurveShape::concave}}).size(), 8u);     // m + 1
  EXPECT_EQ(shape_constraints(knots, {{"volumetric", CurveShape::decreasing}}).size(), 9u);  // m + 2

  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    // Admissible controls: random, then made monotone (convex) on the constrained indices by
    // cumulative sums of non-negative increments (of increments).
    Vector z = Vector::NullaryExpr(knots.num_controls(), [&](Eigen::Index) { return uniform(rng); });
    Vector m = z, c = z;
    for (int k = 1; k <= 6; ++k) m[offset + k] = m[offset + k - 1] + std::abs(uniform(rng));
    double slope = uniform(rng);
    for (int k = 2; k <= 6; ++k) {
      c[offset + k] = c[offset + k - 1] + slope;
      slope += std::abs(uniform(rng));
    }
    EXPECT_TRUE(satisfies(increasing, m, 1e-12));
    EXPECT_GE(min_sampled(m, 0.7, 1.5, false), -1e-12);
    EXPECT_TRUE(satisfies(convex, c, 1e-12));
    EXPECT_GE(min_sampled(c, 0.7, 1.5, true), -1e-12);
  }
  // The Neo-Hookean h decreases up to J = alpha = 1.4 (nu = 0.3): the increasing constraint on
  // [0.7, 1.5] cuts it off; the decreasing one admits it on [0.7, 0.9], whose controls reach up
  // to the knot 1.4 (the condition is sufficient, so it looks one interval beyond the range).
  const Vector neo =
      principal_stretch_preset(SplinePreset::neo_hookean, lame_from_young_poisson(10.0, 0.3), coarse_grids())
          .controls();
  EXPECT_FALSE(satisfies(increasing, neo, 1e-12));
  EXPECT_TRUE(
      satisfies(shape_constraints(knots, {{"volumetric", CurveShape::decreasing, 0.7, 0.9}}), neo, 1e-12));
  // Gradients are the constant rows of the inequalities.
  Vector gradient;
  EXPECT_DOUBLE_EQ(increasing[0].evaluate(neo, &gradient), -(neo[offset + 2] - neo[offset + 1]));
  EXPECT_EQ(gradient[offset + 1], 1.0);
  EXPECT_EQ(gradient[offset + 2], -1.0);
  EXPECT_THROW(shape_constraints(knots, {{"torsional", CurveShape::convex}}), std::invalid_argument);
}

TEST(ShapeConstraints, FitHonoursAnActiveMonotonicityConstraint) {
  testing::TempFolder folder("shape_constraint_fit");
  MaterialFitSpec spec;
  spec.name = "increasing_h";
  spec.grids = coarse_grids();
  spec.cases = {{"pull", LoadCaseKind::uniaxial, {1.1, 1.3}},
                {"squash", LoadCaseKind::uniaxial, {0.8}},
                {"shear", LoadCaseKind::shear, {0.2}},
                {"biaxial", LoadCaseKind::biaxial, {1.15}}};
  spec.reference_preset = SplinePreset::neo_hookean;
  spec.reference_lame = lame_from_young_poisson(10.0, 0.3);
  spec.initial_preset = SplinePreset::corotated;  // h = 0: feasible start
  spec.initial_lame = lame_from_young_poisson(10.0, 0.3);
  spec.smoothness = 1e-4;
  spec.shapes = {{"volumetric", CurveShape::increasing, 0.6, 1.4}};
  spec.optimizer.backend = OptimizerBackend::nlopt_slsqp;
  spec.optimizer.max_iterations = 150;
  const MaterialFitRun run = run_material_fit(spec, folder.str(), nullptr, nullptr);
  const std::vector<Constraint> constraints = shape_constraints(zero_curves(spec.grids), spec.shapes);
  EXPECT_TRUE(satisfies(constraints, run.result.z, 1e-8)) << run.result.report();
  EXPECT_GE(min_sampled(run.result.z, 0.6, 1.4, false), -1e-6);
  // The constraint binds: the unconstrained fit reaches ~1e-6 (MaterialFit.RecoversANeoHookeanResponse).
  EXPECT_GT(run.relative_force_error, 1e-4);
  EXPECT_LT(run.relative_force_error, run.initial_relative_force_error);
}

}  // namespace
}  // namespace tailor::shape_constraints_test
