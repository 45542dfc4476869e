#include "problems/metamaterial/cell_design.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "forward/core/timing.hpp"
#include "forward/homogenization/engineering_constants.hpp"

namespace tailor {
namespace {

// dJ/dC from dJ/dS with S = C^-1: dS = -S dC S, so dJ/dC = -S^T (dJ/dS) S^T.
Matrix chain_compliance(const Matrix& S, const Matrix& dJ_dS) {
  return -S.transpose() * dJ_dS * S.transpose();
}

Vector voigt_of_outer(const Vector& d) { return voigt_stress(d.normalized() * d.normalized().transpose()); }

// Heaviside projection with threshold 1/2 and its derivative (Wang, Lazarov & Sigmund 2011).
double project(double t, double beta) {
  if (beta == 0.0) return t;
  return (std::tanh(0.5 * beta) + std::tanh(beta * (t - 0.5))) / (2.0 * std::tanh(0.5 * beta));
}
double project_derivative(double t, double beta) {
  if (beta == 0.0) return 1.0;
  const double th = std::tanh(beta * (t - 0.5));
  return beta * (1.0 - th * th) / (2.0 * std::tanh(0.5 * beta));
}

}  // namespace

double CellObjective::evaluate(const Matrix& C, Matrix* dJ_dC) const {
  double J = 0.0;
  Matrix dJ = Matrix::Zero(C.rows(), C.cols());
  for (const Entry& e : entries) {
    const double r = (C(e.row, e.col) - e.value) / entry_scale;
    J += e.weight * r * r;
    dJ(e.row, e.col) += 2.0 * e.weight * r / entry_scale;
  }
  const bool needs_compliance = !directions.empty() || !poisson_pairs.empty();
  if (needs_compliance) {
    const Matrix S = compliance(C);
    Matrix dJ_dS = Matrix::Zero(S.rows(), S.cols());
    const double n = static_cast<double>(directions.size());
    for (std::size_t i = 0; i < directions.size(); ++i) {
      // E(d) = 1 / (a^T S a);  dE/dS = -E^2 a a^T.
      const Vector a = voigt_of_outer(directions[i]);
      const double E = 1.0 / a.dot(S * a);
      const double r = E / target_moduli[i] - 1.0;
      J += directional_weight * r * r / (2.0 * n);
      dJ_dS += directional_weight * (r / n) / target_moduli[i] * (-E * E) * a * a.transpose();
    }
    for (const auto& [d, m] : poisson_pairs) {
      // nu = -(b^T S a) / (a^T S a);  dnu/dS = -b a^T / (a^T S a) + (b^T S a) / (a^T S a)^2 a a^T.
      const Vector a = voigt_of_outer(d), b = voigt_of_outer(m);
      const double q = a.dot(S * a), s = b.dot(S * a);
      const double nu = -s / q;
      const double r = nu - poisson_target;
      J += 0.5 * poisson_weight * r * r;
      dJ_dS += poisson_weight * r * (-b * a.transpose() / q + s / (q * q) * a * a.transpose());
    }
    dJ += chain_compliance(S, dJ_dS);
  }
  if (dJ_dC) *dJ_dC = dJ;
  return J;
}

CellDesignFunctional::CellDesignFunctional(std::shared_ptr<LinearCell> cell, SimpMaterial material,
                                           double filter_radius, CellObjective objective)
    : cell_(std::move(cell)),
      material_(material),
      filter_(cell_->cell(), filter_radius),
      objective_(std::move(objective)),
      volumes_(element_volumes(cell_->cell().mesh)) {
  if (!(material_.min_youngs_modulus > 0.0) || !(material_.youngs_modulus > material_.min_youngs_modulus) ||
      !(material_.penalty >= 1.0))
    throw std::invalid_argument("CellDesignFunctional: need 0 < E_min < E_0 and penalty >= 1");
  if (objective_.directions.size() != objective_.target_moduli.size())
    throw std::invalid_argument("CellDesignFunctional: one target modulus per direction");
}

Vector CellDesignFunctional::youngs_moduli(const Vector& rho) const {
  Vector E(rho.size());
  for (int e = 0; e < rho.size(); ++e)
    E[e] = material_.min_youngs_modulus + std::pow(std::clamp(rho[e], 0.0, 1.0), material_.penalty) *
                                              (material_.youngs_modulus - material_.min_youngs_modulus);
  return E;
}

void CellDesignFunctional::set_projection(double beta) {
  if (!(beta >= 0.0) || !std::isfinite(beta))
    throw std::invalid_argument("CellDesignFunctional: projection beta must be >= 0");
  beta_ = beta;
}

Vector CellDesignFunctional::densities(const Vector& z) const {
  Vector rho = filter_.apply(z);
  for (auto& r : rho) r = project(r, beta_);
  return rho;
}

double CellDesignFunctional::evaluate(const Vector& z, Vector* gradient) {
  if (z.size() != size()) throw std::invalid_argument("CellDesignFunctional: wrong design size");
  const Vector filtered = filter_.apply(z);
  const Vector rho = densities(z);
  const auto t0 = Clock::now();
  try {
    last_ = cell_->solve(youngs_moduli(rho), Vector::Constant(size(), material_.poisson_ratio));
  } catch (const std::exception& e) {
    throw EvaluationError(std::string("cell problems failed: ") + e.what());
  }
  ++counters_.evaluations;
  ++counters_.forward_solves;
  counters_.forward_seconds += seconds_since(t0);
  Matrix dJ_dC;
  const double J = objective_.evaluate(last_.stiffness, gradient ? &dJ_dC : nullptr);
  if (gradient) {
    const auto t1 = Clock::now();
    const Vector dJ_dE = cell_->youngs_modulus_gradient(dJ_dC);
    Vector dJ_drho(size());
    for (int e = 0; e < size(); ++e) {
      const double r = std::clamp(rho[e], 0.0, 1.0);
      dJ_drho[e] = dJ_dE[e] * material_.penalty * std::pow(r, material_.penalty - 1.0) *
                   (material_.youngs_modulus - material_.min_youngs_modulus) *
                   project_derivative(filtered[e], beta_);
    }
    *gradient = filter_.apply_transpose(dJ_drho);
    ++counters_.adjoint_solves;
    counters_.adjoint_seconds += seconds_since(t1);
  }
  return J;
}

double CellDesignFunctional::value(const Vector& z) { return evaluate(z, nullptr); }
double CellDesignFunctional::value_and_gradient(const Vector& z, Vector& gradient) {
  return evaluate(z, &gradient);
}

double CellDesignFunctional::volume_fraction(const Vector& z, Vector* gradient) const {
  const double volume = volumes_.sum();
  const Vector filtered = filter_.apply(z);
  if (gradient) {
    Vector g(size());
    for (int e = 0; e < size(); ++e) g[e] = volumes_[e] / volume * project_derivative(filtered[e], beta_);
    *gradient = filter_.apply_transpose(g);
  }
  return volumes_.dot(densities(z)) / volume;
}

}  // namespace tailor
