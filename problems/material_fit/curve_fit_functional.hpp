#pragma once
// The reduced functional of a material fit over the curve control values z (= p, the flat
// [f; g; h] controls of a principal-stretch spline material):
//   J(z) = sum_{case, step} 1/2 ((F_step(x*(z), z) - F*_step) / F_scale)^2 + alpha/2 |D z|^2,
// F_step the measured reaction force of a load step at its equilibrium x*(z) (load_cases.hpp),
// F* its target, D the third differences of the control values of each curve over h^3 (y'''; picks
// one curve among those the load cases cannot tell apart). Each step is a StaticFunctional (its own
// model, warm-started Newton and adjoint); the residual form stacks their residuals, so
// Gauss-Newton (ceres_least_squares) applies.
#include <memory>
#include <vector>

#include "adjoint/static_functional.hpp"
#include "problems/material_fit/load_cases.hpp"

namespace tailor {

struct FitStep {
  int load_case = 0;
  int step = 0;
  double target = 0.0;  // F*
};

class CurveFitFunctional final : public ReducedFunctional {
 public:
  // One StaticFunctional per step, on `mesh` with the knots of `curves`.
  CurveFitFunctional(const Mesh& mesh, std::vector<LoadCase> cases, std::vector<FitStep> steps,
                     PrincipalStretchCurves knots, double force_scale, double smoothness);

  int size() const override { return knots_.num_controls(); }
  double value(const Vector& z) override;
  double value_and_gradient(const Vector& z, Vector& gradient) override;
  bool has_residuals() const override { return true; }
  int num_residuals() const override;
  void residuals(const Vector& z, Vector& r, Matrix* jacobian) override;
  const FunctionalCounters& counters() const override;

  // The measured force of every step at z (solves).
  std::vector<double> forces(const Vector& z);
  const std::vector<FitStep>& steps() const { return steps_; }

 private:
  // Third differences of each curve's controls (y'''), unscaled: rows of D.
  Matrix smoothness_rows() const;

  std::vector<LoadCase> cases_;
  std::vector<FitStep> steps_;
  PrincipalStretchCurves knots_;
  std::vector<SpecimenStep> specimen_steps_;
  std::vector<std::unique_ptr<StaticFunctional>> parts_;
  Matrix smoothing_;  // sqrt(alpha) D
  mutable FunctionalCounters total_;
};

}  // namespace tailor
