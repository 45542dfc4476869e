#pragma once
// Shape constraints on the curves of a material fit, as linear inequalities on the control
// values (the optimizer's Constraint: value <= 0). With c the controls of one uniform cubic
// B-spline (cubic_spline.hpp) and h its knot spacing, on knot interval i
//   y'  = sum_{j=0..2} (c_{i+j+1} - c_{i+j}) / h * N2_j(u),
//   y'' = sum_{j=0..1} (c_{i+j} - 2 c_{i+j+1} + c_{i+j+2}) / h^2 * N1_j(u),
// with N2, N1 the non-negative quadratic and linear B-splines, so the sign of the first
// (second) differences of the controls acting on an interval is a sufficient condition for
// monotonicity (convexity) there (de Boor, "A Practical Guide to Splines", ch. IX/X). The
// linear continuation outside [lower, upper] keeps the end slope, which the first and last
// intervals' differences already bound, and has y'' = 0. Being sufficient, not necessary, a
// constraint on [lower, upper] also restricts the controls that reach into the neighbouring
// intervals.
#include <limits>
#include <string>
#include <vector>

#include "forward/fem/materials/principal_stretch_curves.hpp"
#include "optimizers/optimizer.hpp"

namespace tailor {

enum class CurveShape { increasing, decreasing, convex, concave };
std::string to_string(CurveShape shape);
CurveShape parse_curve_shape(const std::string& name);  // throws std::invalid_argument

struct ShapeConstraint {
  std::string curve;  // "uniaxial", "biaxial" or "volumetric"
  CurveShape shape = CurveShape::convex;
  // Where it must hold, in the curve's own argument (stretch, stretch product, J); the
  // constraint covers every knot interval that meets [lower, upper] (clamped to the curve).
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
};

// One Constraint per control difference, over the flat control vector [f; g; h] of `knots`.
// Throws std::invalid_argument for an unknown curve or lower >= upper.
std::vector<Constraint> shape_constraints(const PrincipalStretchCurves& knots,
                                          const std::vector<ShapeConstraint>& shapes);

// Whether every inequality holds at z to within `tolerance` (scaled by the controls' size).
bool satisfies(const std::vector<Constraint>& constraints, const Vector& z, double tolerance);

}  // namespace tailor
