#include "adjoint/reduced_equilibrium_functional.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <stdexcept>
#include <string>

#include "forward/core/timing.hpp"
#include "forward/reduction/polynomial_design_model.hpp"

namespace tailor {

ReducedEquilibriumFunctional::ReducedEquilibriumFunctional(ReducedEquilibriumData data,
                                                           ReducedEquilibriumOptions options)
    : data_(std::move(data)), options_(options) {
  const auto fail = [](const std::string& what) {
    throw std::invalid_argument("ReducedEquilibriumFunctional: " + what);
  };
  r_ = static_cast<int>(data_.load.size());
  if (r_ < 1) fail("empty load (r = 0)");
  if (data_.model) {
    if (data_.base.size() > 0 || !data_.modes.empty()) fail("give either a model or polynomial coefficients");
    if (data_.model->size() != r_)
      fail("the model has " + std::to_string(data_.model->size()) + " coordinates, the load " +
           std::to_string(r_));
    if (data_.model->design_size() < 1) fail("no design coordinate (no material mode)");
    model_ = data_.model;
  } else {
    // The coefficients move into the polynomial model (data().model then points to it).
    model_ = std::make_shared<PolynomialDesignModel>(std::move(data_.base), std::move(data_.modes), r_,
                                                     "ReducedEquilibriumFunctional");
    data_.base = Matrix();
    data_.modes.clear();
    data_.model = model_;
  }
  if (data_.rows.cols() != r_) fail("the observation rows need r = " + std::to_string(r_) + " columns");
  if (data_.target.size() != data_.rows.rows() || data_.row_weights.size() != data_.rows.rows())
    fail("target and row weights need one entry per observation row");
  if ((data_.row_weights.array() < 0.0).any()) fail("negative row weight");
  if (data_.regularization.size() == 0) data_.regularization = Vector::Zero(size());
  if (data_.regularization.size() != size()) fail("the regularization needs one entry per design coordinate");
  if ((data_.regularization.array() < 0.0).any()) fail("negative regularization");
  if (!(options_.tolerance > 0.0) || options_.max_iterations < 1) fail("bad Newton options");
  if (data_.element_modes.size() > 0) {
    if (data_.element_modes.cols() != size()) fail("the element modes need one column per design coordinate");
    if (data_.element_weights.size() != data_.element_modes.rows()) fail("one element weight per element");
    if (!(data_.positivity_floor > 0.0 && data_.positivity_floor < 1.0))
      fail("positivity floor not in (0, 1)");
    if (!(data_.positivity_weight >= 0.0)) fail("negative positivity weight");
  }
}

Matrix ReducedEquilibriumFunctional::coefficients(const Vector& w) const {
  const auto* polynomial = dynamic_cast<const PolynomialDesignModel*>(model_.get());
  if (!polynomial)
    throw std::invalid_argument("ReducedEquilibriumFunctional: the " + model_->name() +
                                " model has no polynomial coefficients");
  return polynomial->coefficients(w);
}

void ReducedEquilibriumFunctional::evaluate(const Vector& q, const Vector& w, double* energy, Vector* force,
                                            Matrix* stiffness) const {
  if (q.size() != r_)
    throw std::invalid_argument("ReducedEquilibriumFunctional: q has " + std::to_string(q.size()) +
                                " entries, expected " + std::to_string(r_));
  if (w.size() != size())
    throw std::invalid_argument("ReducedEquilibriumFunctional: w has " + std::to_string(w.size()) +
                                " entries, expected " + std::to_string(size()));
  model_->evaluate(q, w, energy, force, stiffness);
}

const Vector& ReducedEquilibriumFunctional::solve(const Vector& w) {
  if (have_state_ && w == w_) return q_;
  const auto t0 = Clock::now();
  if (w.size() != size())
    throw std::invalid_argument("ReducedEquilibriumFunctional: w has " + std::to_string(w.size()) +
                                " entries, expected " + std::to_string(size()));
  // E.g. the polynomial's G(w) once per solve, not per Newton iteration.
  const ReducedDesignModel::AtDesign evaluate_at = model_->at_design(w);
  Vector q = (options_.warm_start && have_state_) ? q_ : Vector::Zero(r_);
  const Vector& f = data_.load;
  double energy = 0.0;
  Vector force;
  Matrix k;
  bool converged = false;
  int it = 0;
  std::string why = "no convergence in " + std::to_string(options_.max_iterations) + " iterations";
  for (; it <= options_.max_iterations; ++it) {
    evaluate_at(q, &energy, &force, &k);
    const Vector residual = force - f;
    const double scale = std::max(f.norm(), force.norm());
    if (!std::isfinite(residual.norm())) {
      why = "non-finite residual";
      break;
    }
    if (residual.norm() <= options_.tolerance * scale || scale == 0.0) {
      converged = true;
      break;
    }
    if (it == options_.max_iterations) break;
    Vector step;
    Eigen::LLT<Matrix> llt(k);
    if (llt.info() == Eigen::Success) {
      step = -llt.solve(residual);
    } else {
      Eigen::LDLT<Matrix> ldlt(k);
      step = -ldlt.solve(residual);
    }
    if (!step.allFinite()) {
      why = "singular reduced stiffness";
      break;
    }
    // Backtracking on the potential W - f.q, or accept a smaller residual.
    const double potential = energy - f.dot(q), slope = residual.dot(step);
    double t = 1.0;
    bool accepted = false;
    for (int ls = 0; ls < 40 && !accepted; ++ls, t *= 0.5) {
      const Vector trial = q + t * step;
      double e_trial = 0.0;
      Vector f_trial;
      evaluate_at(trial, &e_trial, &f_trial, nullptr);
      const double p_trial = e_trial - f.dot(trial);
      if (std::isfinite(p_trial) && (p_trial <= potential + 1e-4 * t * std::min(slope, 0.0) ||
                                     (f_trial - f).norm() < residual.norm())) {
        q = trial;
        accepted = true;
      }
    }
    if (!accepted) {
      why = "line search failed";
      break;
    }
    if ((t * 2.0) * step.norm() <= 1e-15 * (1.0 + q.norm())) {
      evaluate_at(q, &energy, &force, &k);
      converged = true;
      break;
    }
  }
  ++counters_.forward_solves;
  counters_.forward_seconds += seconds_since(t0);
  last_iterations_ = it;
  if (!converged) {
    have_state_ = false;
    throw EvaluationError("reduced equilibrium: " + why);
  }
  q_ = q;
  w_ = w;
  stiffness_ = k;
  have_state_ = true;
  return q_;
}

void ReducedEquilibriumFunctional::set_observations(Vector target, Vector row_weights) {
  if (target.size() != data_.rows.rows() || row_weights.size() != data_.rows.rows())
    throw std::invalid_argument("ReducedEquilibriumFunctional::set_observations: " +
                                std::to_string(data_.rows.rows()) + " targets and weights wanted, got " +
                                std::to_string(target.size()) + " and " + std::to_string(row_weights.size()));
  if (!target.allFinite() || !row_weights.allFinite() || (row_weights.array() < 0.0).any())
    throw std::invalid_argument(
        "ReducedEquilibriumFunctional::set_observations: targets must be finite, weights finite and >= 0");
  data_.target = std::move(target);
  data_.row_weights = std::move(row_weights);
}

double ReducedEquilibriumFunctional::misfit() const {
  const Vector residual = data_.rows * q_ - data_.target;
  return 0.5 * (data_.row_weights.array() * residual.array().square()).sum();
}

double design_terms(const ReducedEquilibriumData& data, const Vector& w, Vector* gradient) {
  double value = 0.0;
  if (data.regularization.size() > 0) {
    value += 0.5 * (data.regularization.array() * w.array().square()).sum();
    if (gradient) *gradient += data.regularization.cwiseProduct(w);
  }
  if (data.element_modes.size() == 0) return value;
  const Vector e = Vector::Ones(data.element_modes.rows()) + data.element_modes * w;
  Eigen::Index worst = 0;
  if (e.minCoeff(&worst) <= 0.0)
    throw EvaluationError("material design: the relative modulus of element " + std::to_string(worst) +
                          " is " + std::to_string(e[worst]) + " <= 0");
  const double eps = data.positivity_floor, kappa = data.positivity_weight;
  Vector de = Vector::Zero(e.size());
  bool active = false;
  for (Eigen::Index k = 0; k < e.size(); ++k) {
    const double d = (eps - e[k]) / eps;
    if (d <= 0.0) continue;
    active = true;
    value += kappa / 3.0 * data.element_weights[k] * d * d * d;
    de[k] = -kappa * data.element_weights[k] * d * d / eps;
  }
  if (gradient && active) gradient->noalias() += data.element_modes.transpose() * de;
  return value;
}

double ReducedEquilibriumFunctional::value(const Vector& w) {
  ++counters_.evaluations;
  const double design = design_terms(data_, w, nullptr);
  solve(w);
  return misfit() + design;
}

double ReducedEquilibriumFunctional::value_and_gradient(const Vector& w, Vector& gradient) {
  ++counters_.evaluations;
  Vector design_gradient = Vector::Zero(size());
  const double design = design_terms(data_, w, &design_gradient);
  solve(w);
  const auto t0 = Clock::now();
  const Vector residual = data_.rows * q_ - data_.target;
  const Vector rhs = data_.rows.transpose() * data_.row_weights.cwiseProduct(residual);
  Eigen::LDLT<Matrix> ldlt(stiffness_);
  const Vector lambda = ldlt.solve(rhs);
  if (ldlt.info() != Eigen::Success || !lambda.allFinite())
    throw EvaluationError("reduced adjoint: singular reduced stiffness");
  // dJ/dw = -lambda^T d(dW/dq)/dw + the design terms' gradient.
  const Vector mixed = model_->force_design_derivative_transpose(q_, lambda);
  if (!mixed.allFinite()) throw EvaluationError("reduced adjoint: the mixed derivative is not finite");
  gradient = design_gradient - mixed;
  ++counters_.adjoint_solves;
  counters_.adjoint_seconds += seconds_since(t0);
  return misfit() + design;
}

}  // namespace tailor
