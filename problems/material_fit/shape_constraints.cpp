#include "problems/material_fit/shape_constraints.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tailor {
namespace {

// value = -(sign * sum_k weights[k] z[first + k]) <= 0, i.e. the signed difference is >= 0.
Constraint difference_constraint(std::string name, int n, int first, std::vector<double> weights,
                                 double sign) {
  return {std::move(name), false,
          [n, first, weights = std::move(weights), sign](const Vector& z, Vector* gradient) {
            double value = 0.0;
            if (gradient) gradient->setZero(n);
            for (std::size_t k = 0; k < weights.size(); ++k) {
              const int i = first + static_cast<int>(k);
              value -= sign * weights[k] * z[i];
              if (gradient) (*gradient)[i] = -sign * weights[k];
            }
            return value;
          }};
}

}  // namespace

std::string to_string(CurveShape shape) {
  switch (shape) {
    case CurveShape::increasing:
      return "increasing";
    case CurveShape::decreasing:
      return "decreasing";
    case CurveShape::convex:
      return "convex";
    case CurveShape::concave:
      return "concave";
  }
  return "?";
}

CurveShape parse_curve_shape(const std::string& name) {
  for (CurveShape s :
       {CurveShape::increasing, CurveShape::decreasing, CurveShape::convex, CurveShape::concave})
    if (to_string(s) == name) return s;
  throw std::invalid_argument("unknown curve shape '" + name + "' (increasing, decreasing, convex, concave)");
}

std::vector<Constraint> shape_constraints(const PrincipalStretchCurves& knots,
                                          const std::vector<ShapeConstraint>& shapes) {
  const int n = knots.num_controls();
  const CubicSpline* curves[3] = {&knots.uniaxial, &knots.biaxial, &knots.volumetric};
  const char* names[3] = {"uniaxial", "biaxial", "volumetric"};
  std::vector<Constraint> constraints;
  for (const ShapeConstraint& s : shapes) {
    int c = 0, offset = 0;
    while (c < 3 && s.curve != names[c]) offset += curves[c++]->num_controls();
    if (c == 3) throw std::invalid_argument("shape constraint: unknown curve '" + s.curve + "'");
    if (!(s.lower < s.upper)) throw std::invalid_argument("shape constraint: expected lower < upper");
    const CubicSpline& curve = *curves[c];
    const int m = curve.intervals();
    const double h = curve.spacing();
    // Knot intervals meeting [lower, upper], clamped to 0 .. m-1 (the continuation beyond the
    // ends is governed by the end intervals).
    const auto clamp = [m](double v) { return static_cast<int>(std::clamp(v, 0.0, double(m - 1))); };
    const int first = clamp(std::floor((s.lower - curve.lower()) / h));
    const int last = std::max(first, clamp(std::ceil((s.upper - curve.lower()) / h) - 1.0));
    const std::string prefix = std::string(names[c]) + "_" + to_string(s.shape) + "_";
    const bool monotone = s.shape == CurveShape::increasing || s.shape == CurveShape::decreasing;
    const double sign = s.shape == CurveShape::increasing || s.shape == CurveShape::convex ? 1.0 : -1.0;
    if (monotone)
      for (int k = first; k <= last + 2; ++k)  // c_{k+1} - c_k acts on intervals k-2 .. k
        constraints.push_back(
            difference_constraint(prefix + std::to_string(k), n, offset + k, {-1.0, 1.0}, sign));
    else
      for (int k = first + 1; k <= last + 2; ++k)  // c_{k-1} - 2 c_k + c_{k+1} acts on intervals k-2, k-1
        constraints.push_back(
            difference_constraint(prefix + std::to_string(k), n, offset + k - 1, {1.0, -2.0, 1.0}, sign));
  }
  return constraints;
}

bool satisfies(const std::vector<Constraint>& constraints, const Vector& z, double tolerance) {
  const double scale = std::max(1.0, z.cwiseAbs().maxCoeff());
  return std::all_of(constraints.begin(), constraints.end(),
                     [&](const Constraint& c) { return c.evaluate(z, nullptr) <= tolerance * scale; });
}

}  // namespace tailor
