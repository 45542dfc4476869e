#include "problems/material_fit/curve_fit_functional.hpp"

#include <cmath>

namespace tailor {

CurveFitFunctional::CurveFitFunctional(const Mesh& mesh, std::vector<LoadCase> cases,
                                       std::vector<FitStep> steps, PrincipalStretchCurves knots,
                                       double force_scale, double smoothness)
    : cases_(std::move(cases)), steps_(std::move(steps)), knots_(std::move(knots)) {
  for (const FitStep& s : steps_) {
    specimen_steps_.push_back(spline_load_step(mesh, cases_.at(s.load_case), s.step, knots_));
    const SpecimenStep& ls = specimen_steps_.back();
    parts_.push_back(std::make_unique<StaticFunctional>(*ls.model, identity_map(knots_.num_controls()),
                                                        reaction_objective(ls, s.target, force_scale),
                                                        ls.rest_y));
  }
  smoothing_ = std::sqrt(smoothness) * smoothness_rows();
}

Matrix CurveFitFunctional::smoothness_rows() const {
  const int sizes[3] = {knots_.uniaxial.num_controls(), knots_.biaxial.num_controls(),
                        knots_.volumetric.num_controls()};
  // Third differences of the controls over h^3 are y''' on each interval (a cubic piece has a
  // constant third derivative), times h^(1/2) so the sum of squares approximates the integral of
  // y'''^2. Penalising y''' (not y'') leaves quadratic curves free: the Neo-Hookean, corotated
  // and linear responses are not biased, while directions the load cases cannot see are damped.
  const double spacing[3] = {knots_.uniaxial.spacing(), knots_.biaxial.spacing(),
                             knots_.volumetric.spacing()};
  int rows = 0;
  for (int n : sizes) rows += n - 3;
  Matrix D = Matrix::Zero(rows, size());
  int row = 0, offset = 0;
  for (int c = 0; c < 3; ++c) {
    const double w = std::sqrt(spacing[c]) / (spacing[c] * spacing[c] * spacing[c]);
    for (int k = 0; k + 3 < sizes[c]; ++k, ++row) {
      D(row, offset + k) = -w;
      D(row, offset + k + 1) = 3.0 * w;
      D(row, offset + k + 2) = -3.0 * w;
      D(row, offset + k + 3) = w;
    }
    offset += sizes[c];
  }
  return D;
}

int CurveFitFunctional::num_residuals() const {
  int n = static_cast<int>(smoothing_.rows());
  for (const auto& p : parts_) n += p->num_residuals();
  return n;
}

double CurveFitFunctional::value(const Vector& z) {
  double J = 0.5 * (smoothing_ * z).squaredNorm();
  for (auto& p : parts_) J += p->value(z);
  return J;
}

double CurveFitFunctional::value_and_gradient(const Vector& z, Vector& gradient) {
  const Vector Dz = smoothing_ * z;
  double J = 0.5 * Dz.squaredNorm();
  gradient = smoothing_.transpose() * Dz;
  Vector g;
  for (auto& p : parts_) {
    J += p->value_and_gradient(z, g);
    gradient += g;
  }
  return J;
}

void CurveFitFunctional::residuals(const Vector& z, Vector& r, Matrix* jacobian) {
  r.resize(num_residuals());
  if (jacobian) jacobian->resize(num_residuals(), size());
  int row = 0;
  Vector rp;
  Matrix jp;
  for (auto& p : parts_) {
    p->residuals(z, rp, jacobian ? &jp : nullptr);
    r.segment(row, rp.size()) = rp;
    if (jacobian) jacobian->middleRows(row, rp.size()) = jp;
    row += static_cast<int>(rp.size());
  }
  r.tail(smoothing_.rows()) = smoothing_ * z;
  if (jacobian) jacobian->bottomRows(smoothing_.rows()) = smoothing_;
}

const FunctionalCounters& CurveFitFunctional::counters() const {
  total_ = FunctionalCounters{};
  for (const auto& p : parts_) {
    const FunctionalCounters& c = p->counters();
    total_.evaluations = std::max(total_.evaluations, c.evaluations);
    total_.forward_solves += c.forward_solves;
    total_.adjoint_solves += c.adjoint_solves;
    total_.forward_seconds += c.forward_seconds;
    total_.adjoint_seconds += c.adjoint_seconds;
  }
  return total_;
}

std::vector<double> CurveFitFunctional::forces(const Vector& z) {
  std::vector<double> f;
  for (std::size_t i = 0; i < parts_.size(); ++i) {
    parts_[i]->value(z);
    f.push_back(measured_force(specimen_steps_[i], parts_[i]->state(), z));
  }
  return f;
}

}  // namespace tailor
