#include "adjoint/static_functional.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "forward/core/format_number.hpp"
#include "forward/core/timing.hpp"
#include "forward/fem/parameter_refused.hpp"
#include "forward/solve/preconditioned_cg.hpp"

namespace tailor {
std::string to_string(HessianSolve method) {
  switch (method) {
    case HessianSolve::reused_factorization: return "reused_factorization";
    case HessianSolve::preconditioned_cg: return "preconditioned_cg";
    case HessianSolve::fresh_factorization: return "fresh_factorization";
    case HessianSolve::external_solver: return "external_solver";
  }
  return "unknown";
}

StaticFunctional::StaticFunctional(const Model& model, ParameterizationPtr parameterization, ObjectivePtr objective,
                                   Vector rest_y, StaticFunctionalOptions options)
    : model_(model),
      parameterization_(std::move(parameterization)),
      objective_(std::move(objective)),
      options_(options),
      newton_(model, options.newton),
      rest_y_(std::move(rest_y)) {
  if (!parameterization_ || !objective_) throw std::invalid_argument("StaticFunctional: parameterization and objective are required");
  if (parameterization_->num_params() != model.parameter_layout().size())
    throw std::invalid_argument("StaticFunctional: the parameterization produces " +
                                std::to_string(parameterization_->num_params()) + " parameters, the model has " +
                                std::to_string(model.parameter_layout().size()));
  if (rest_y_.size() != model.elimination().num_free())
    throw std::invalid_argument("StaticFunctional: the initial state has the wrong number of unknowns");
}

namespace {

// An optimizer's trial point, or a caller's design, may be NaN or overflow its map (z = log E
// above 709): an EvaluationError, which back-ends answer by shortening the step, never a
// solve with non-finite numbers.
void check_design(const Vector& z) {
  for (Eigen::Index k = 0; k < z.size(); ++k)
    if (!std::isfinite(z[k]))
      throw EvaluationError("the design is not finite: z[" + std::to_string(k) + "] = " + format_number(z[k]));
}

void check_parameters(const Vector& p) {
  for (Eigen::Index k = 0; k < p.size(); ++k)
    if (!std::isfinite(p[k]))
      throw EvaluationError("the model parameters at this design are not finite: p[" + std::to_string(k) +
                            "] = " + format_number(p[k]) + " (the design overflows its map)");
}

}  // namespace

// A model that refuses the parameters (a material with E <= 0 or nu >= 1/2 at this design) is a
// failed evaluation too.
NewtonResult StaticFunctional::solve_refusing(const Vector& p, Vector& y) {
  try {
    return newton_.solve(p, y);
  } catch (const ParameterRefused& e) {
    throw EvaluationError(std::string("the model refuses the parameters at this design: ") + e.what());
  }
}

void StaticFunctional::forward(const Vector& z) {
  if (z.size() != size())
    throw std::invalid_argument("StaticFunctional: z has " + std::to_string(z.size()) + " entries, expected " +
                                std::to_string(size()));
  if (have_state_ && z == z_) return;
  const auto t0 = Clock::now();
  check_design(z);
  p_ = parameterization_->apply(z);
  check_parameters(p_);
  const bool warm = options_.warm_start && have_state_;
  Vector y = warm ? y_ : rest_y_;
  have_state_ = false;
  // A warm start measures convergence against the residual a cold start would begin with.
  newton_.options().reference_residual = 0.0;
  if (warm) {
    Vector g_rest;
    newton_.assembler().evaluate(rest_y_, p_, nullptr, &g_rest, nullptr);
    newton_.options().reference_residual = g_rest.norm();
  }
  adjoint_solver_ready_ = false;  // Newton's steps set the linear solver up with other matrices
  first_.reset();
  products_.reset();
  newton_result_ = solve_refusing(p_, y);
  ++counters_.forward_solves;
  if (!newton_result_.converged() && warm) {
    y = rest_y_;  // a warm start can sit in another basin; retry from rest once
    newton_.options().reference_residual = 0.0;
    newton_result_ = solve_refusing(p_, y);
    ++counters_.forward_solves;
  }
  counters_.forward_seconds += seconds_since(t0);
  count_factor_work();
  if (!newton_result_.converged())
    throw EvaluationError("forward solve failed: " + to_string(newton_result_.status) + " (" + newton_result_.message + ")");
  y_ = y;
  x_ = model_.state(y_, p_);
  z_ = z;
  objective_value_ = objective_->value(x_, p_);
  have_state_ = true;
  ++counters_.evaluations;
}

void StaticFunctional::count_factor_work() {
  counters_.factorizations = newton_.factorization().numeric_factorizations();
  counters_.back_solves = newton_.factorization().back_solves();
}

double StaticFunctional::value(const Vector& z) {
  forward(z);
  return objective_value_;
}

Vector StaticFunctional::solve_hessian(const Vector& rhs) {
  const auto t0 = Clock::now();
  ++counters_.adjoint_solves;
  if (newton_.options().linear_solver) {
    // The alternative linear solver (NewtonOptions::linear_solver) on the exact Hessian at the
    // equilibrium, to options_.linear_relative_tolerance (see the header for the rule).
    LinearSolver& solver = *newton_.options().linear_solver;
    if (!adjoint_solver_ready_ && newton_.assembles_by_parts()) {
      // Distributed assembly: the processes' shares of the exact Hessian at the equilibrium
      // (after a converged solve usually the solver's last set-up already).
      std::string message;
      if (!newton_.set_up_exact_share(p_, y_, message))
        throw EvaluationError("adjoint: linear solver '" + solver.name() + "' set-up failed: " + message);
      adjoint_solver_ready_ = true;
    }
    if (!adjoint_solver_ready_) {
      // After a converged solve Newton's last assembled Hessian is the one at the equilibrium.
      const SparseMatrix* h = &newton_.hessian();
      if (newton_.assembled_mode() != HessianMode::exact) {
        newton_.assembler().evaluate(y_, p_, nullptr, nullptr, &adjoint_hessian_, HessianMode::exact);
        h = &adjoint_hessian_;
      }
      std::string message;
      if (!solver.setup(*h, message))
        throw EvaluationError("adjoint: linear solver '" + solver.name() + "' set-up failed: " + message);
      adjoint_solver_ready_ = true;
    }
    Vector v;
    last_linear_solve_ = solver.solve(rhs, options_.linear_relative_tolerance, v);
    if (!last_linear_solve_.converged)
      throw EvaluationError("adjoint: linear solver '" + solver.name() + "' did not converge: " +
                            last_linear_solve_.message);
    last_solve_ = HessianSolve::external_solver;
    last_cg_iterations_ = last_linear_solve_.iterations;
    counters_.adjoint_seconds += seconds_since(t0);
    return v;
  }
  SparseCholesky& factor = newton_.factorization();
  const bool exact_matrix = newton_.assembled_mode() == HessianMode::exact;
  if (exact_matrix && newton_.factorization_matches_hessian() && newton_.factorization_is_exact()) {
    last_solve_ = HessianSolve::reused_factorization;
    last_cg_iterations_ = 0;
    Vector v = factor.solve(rhs);
    counters_.adjoint_seconds += seconds_since(t0);
    count_factor_work();
    return v;
  }
  // With NewtonOptions::reuse_factorization the kept factor can be of another design. The
  // contraction per iteration that Newton's last CG achieved with it predicts how many
  // iterations this solve's tolerance needs; when more than the cap, factorize at once.
  bool poor_preconditioner = false;
  if (!newton_result_.history.empty()) {
    const NewtonIteration& last = newton_result_.history.back();
    if (last.reused_factorization && last.cg_iterations > 0 && last.cg_relative_residual > 0.0) {
      const double rate = std::pow(last.cg_relative_residual, 1.0 / last.cg_iterations);
      poor_preconditioner = rate >= 1.0 || std::log(options_.linear_relative_tolerance) / std::log(rate) >
                                               options_.max_cg_iterations;
    }
  }
  if (exact_matrix && !poor_preconditioner && newton_.factorization_is_exact() && factor.has_factor() &&
      !factor.is_ldlt()) {
    // Preconditioned CG on H, preconditioned by the factorization of the previous Newton
    // iterate's exact Hessian, which differs from H by O(|dx|).
    Vector v;
    const PcgResult cg = preconditioned_cg(newton_.hessian(), factor, rhs, options_.linear_relative_tolerance,
                                           options_.max_cg_iterations, v);
    if (cg.converged) {
      last_solve_ = HessianSolve::preconditioned_cg;
      last_cg_iterations_ = cg.iterations;
      counters_.adjoint_seconds += seconds_since(t0);
      count_factor_work();
      return v;
    }
  }
  // Factorize the exact Hessian at the equilibrium; later solves at this state reuse it.
  const FactorizationResult f = newton_.factorize_hessian(p_, y_, HessianMode::exact);
  count_factor_work();
  if (!f.success) throw EvaluationError("adjoint: the Hessian at the equilibrium is singular (" + f.message + ")");
  last_solve_ = HessianSolve::fresh_factorization;
  last_cg_iterations_ = 0;
  Vector v = factor.solve(rhs);
  counters_.adjoint_seconds += seconds_since(t0);
  count_factor_work();
  return v;
}

Vector StaticFunctional::adjoint_gradient_p(const Vector& jx, Vector jp, Vector* lambda_out, const SparseMatrix* mixed) {
  const Elimination& elim = model_.elimination();
  const Vector lambda = elim.expand_direction(solve_hessian(elim.reduce(jx)));
  if (mixed)
    jp -= mixed->transpose() * lambda;
  else
    jp -= model_.mixed_transpose_times(x_, p_, lambda);
  if (model_.has_prescribed_parameters()) {
    // x depends on p directly through D: dJ/dp += D^T (J_x - E_xx S lambda).
    jp += model_.prescribed_parameters().transpose() * (jx - model_.hessian_times(x_, p_, lambda));
  }
  if (lambda_out) *lambda_out = lambda;
  return jp;
}

const StaticFunctional::FirstOrder& StaticFunctional::first_order() {
  if (first_) return *first_;
  FirstOrder f;
  f.jx = Vector::Zero(x_.size());
  objective_->add_gradient_x(x_, p_, f.jx);
  Vector jp = Vector::Zero(p_.size());
  objective_->add_gradient_p(x_, p_, jp);
  f.gradient_p = adjoint_gradient_p(f.jx, std::move(jp), &f.lambda);
  first_ = std::move(f);
  return *first_;
}

const StaticFunctional::ProductData& StaticFunctional::product_data(bool residual_jacobians) {
  if (!newton_.options().linear_solver && !(newton_.assembled_mode() == HessianMode::exact &&
                                            newton_.factorization_matches_hessian() &&
                                            newton_.factorization_is_exact())) {
    // Each product solves with H twice: one factorization now instead of CG with another
    // iterate's factor in every solve.
    const FactorizationResult f = newton_.factorize_hessian(p_, y_, HessianMode::exact);
    count_factor_work();
    if (!f.success)
      throw EvaluationError("Hessian-vector product: the Hessian at the equilibrium is singular (" + f.message + ")");
  }
  if (!products_) {
    products_.emplace(ProductData{model_.mixed(x_, p_), {}, {}, false});
  }
  if (residual_jacobians && !products_->residual_jacobians) {
    Vector r;
    objective_->residuals(x_, p_, r, &products_->dr_dx, &products_->dr_dp);
    products_->residual_jacobians = true;
  }
  return *products_;
}

Vector StaticFunctional::tangent(const Vector& dp, const SparseMatrix& mixed) {
  const Elimination& elim = model_.elimination();
  const bool prescribed = model_.has_prescribed_parameters();
  const Vector direct = prescribed ? Vector(model_.prescribed_parameters() * dp) : Vector::Zero(x_.size());
  Vector forcing = mixed * dp;
  if (prescribed) forcing += model_.hessian_times(x_, p_, direct);
  return direct + elim.expand_direction(solve_hessian(-elim.reduce(forcing)));
}

double StaticFunctional::value_and_gradient(const Vector& z, Vector& gradient) {
  forward(z);
  gradient = parameterization_->jacobian_transpose_times(z, first_order().gradient_p);
  return objective_value_;
}

Vector StaticFunctional::hessian_vector(const Vector& z, const Vector& v) {
  if (!objective_->has_second_derivatives())
    throw std::logic_error("StaticFunctional: the objective '" + objective_->name() + "' has no second derivatives");
  if (v.size() != size()) throw std::invalid_argument("StaticFunctional::hessian_vector: v has the wrong size");
  forward(z);
  const Elimination& elim = model_.elimination();
  const ProductData& data = product_data(false);
  const FirstOrder& first = first_order();
  const Vector& lambda = first.lambda;
  ++counters_.hessian_vectors;

  // Tangent: dp = phi' v, dx = D dp + S dy with H dy = -S^T (E_xp dp + E_xx D dp).
  const Vector dp = parameterization_->jacobian_times(z, v);
  const Vector dx = tangent(dp, data.mixed);

  // Third-derivative contractions along (dx, dp) by central differences (see header).
  double relative = 0.0;
  const double x_scale = std::max(x_.lpNorm<Eigen::Infinity>(), 1e-300);
  relative = std::max(relative, dx.lpNorm<Eigen::Infinity>() / x_scale);
  for (Eigen::Index i = 0; i < p_.size(); ++i)
    if (dp[i] != 0.0) relative = std::max(relative, std::abs(dp[i]) / std::max(std::abs(p_[i]), 1e-300));
  Vector d_hessian_lambda = Vector::Zero(x_.size()), d_mixed_lambda = Vector::Zero(p_.size());
  if (relative > 0.0) {
    const double eps = 1e-5 / relative;
    const Vector xp = x_ + eps * dx, xm = x_ - eps * dx, pp = p_ + eps * dp, pm = p_ - eps * dp;
    d_hessian_lambda = (model_.hessian_times(xp, pp, lambda) - model_.hessian_times(xm, pm, lambda)) / (2 * eps);
    d_mixed_lambda = (model_.mixed_transpose_times(xp, pp, lambda) - model_.mixed_transpose_times(xm, pm, lambda)) / (2 * eps);
  }

  // Second-order adjoint: H mu = S^T (J_xx dx + J_xp dp - d(E_xx) lambda).
  Vector ox = Vector::Zero(x_.size()), op = Vector::Zero(p_.size());
  objective_->add_hessian_times(x_, p_, dx, dp, ox, op);
  const Vector mu = elim.expand_direction(solve_hessian(elim.reduce(ox - d_hessian_lambda)));
  Vector hp = op - d_mixed_lambda - data.mixed.transpose() * mu;
  if (model_.has_prescribed_parameters())
    hp += model_.prescribed_parameters().transpose() * (ox - d_hessian_lambda - model_.hessian_times(x_, p_, mu));
  return parameterization_->jacobian_transpose_times(z, hp) + parameterization_->second_derivative_times(z, first.gradient_p, v);
}

Vector StaticFunctional::gauss_newton_vector(const Vector& z, const Vector& v) {
  if (!objective_->is_least_squares())
    throw std::logic_error("StaticFunctional: the objective '" + objective_->name() + "' has no residual form");
  if (v.size() != size()) throw std::invalid_argument("StaticFunctional::gauss_newton_vector: v has the wrong size");
  forward(z);
  const ProductData& data = product_data(true);
  ++counters_.hessian_vectors;
  // w = (dr/dz) v = dr/dx dx + dr/dp dp along the tangent; then (dr/dz)^T w is the gradient of
  // the linear objective w . r by the adjoint.
  const Vector dp = parameterization_->jacobian_times(z, v);
  const Vector dx = tangent(dp, data.mixed);
  const Vector w = data.dr_dx * dx + data.dr_dp * dp;
  const Vector jx = data.dr_dx.transpose() * w;
  const Vector gp = adjoint_gradient_p(jx, data.dr_dp.transpose() * w, nullptr, &data.mixed);
  return parameterization_->jacobian_transpose_times(z, gp);
}

bool StaticFunctional::gauss_newton_diagonal(const Vector& z, Vector& diagonal) {
  if (!objective_->is_least_squares()) return false;
  forward(z);
  const ProductData& data = product_data(true);
  const SparseMatrix& h = newton_.hessian();
  const SparseMatrix& basis = model_.elimination().basis();
  if (h.rows() != basis.cols() || h.cols() != basis.cols() || h.rows() == 0) return false;
  // Jacobi sensitivity dx/dp ~ -S diag(H)^-1 S^T E_xp: the response of each DOF to a
  // parameter's force, without its spread through the rest of the body (the response of a
  // self-equilibrated element force decays fast, so the local part keeps the element's stress
  // level and stiffness).
  Vector inverse_diagonal = h.diagonal();
  for (Eigen::Index i = 0; i < inverse_diagonal.size(); ++i)
    inverse_diagonal[i] = inverse_diagonal[i] > 0.0 ? 1.0 / inverse_diagonal[i] : 0.0;
  const SparseMatrix reduced_mixed = basis.transpose() * data.mixed;
  const SparseMatrix sensitivity = -(basis * (inverse_diagonal.asDiagonal() * reduced_mixed));
  const SparseMatrix jacobian = data.dr_dx * sensitivity + data.dr_dp;  // approximate dr/dp
  Vector d_p = Vector::Zero(p_.size());
  for (Eigen::Index j = 0; j < jacobian.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(jacobian, j); it; ++it)
      d_p[it.col()] += it.value() * it.value();
  // To z: sum_i (dp_i/dz_j)^2 d_i = [phi'^T (d (.) phi' r)]_j r_j for every sign vector r when
  // each p_i depends on at most one z_j; two sign vectors that disagree reveal a map without.
  const Eigen::Index n = size();
  Vector ones = Vector::Ones(n), signs(n);
  for (Eigen::Index j = 0; j < n; ++j) signs[j] = ((j * 2654435761u) >> 7) % 2 ? 1.0 : -1.0;
  diagonal = parameterization_->jacobian_transpose_times(
      z, (d_p.array() * parameterization_->jacobian_times(z, ones).array()).matrix());
  const Vector check =
      parameterization_->jacobian_transpose_times(
          z, (d_p.array() * parameterization_->jacobian_times(z, signs).array()).matrix())
          .cwiseProduct(signs);
  const double scale = diagonal.cwiseAbs().maxCoeff();
  if (!diagonal.allFinite() || !(scale > 0.0) || (diagonal - check).lpNorm<Eigen::Infinity>() > 1e-12 * scale)
    return false;
  // A variable the estimate does not see (no data, no regularizer on it) gets the smallest
  // positive value rather than zero, so that the preconditioner stays positive definite.
  double smallest = scale;
  for (Eigen::Index j = 0; j < n; ++j)
    if (diagonal[j] > 0.0) smallest = std::min(smallest, diagonal[j]);
  for (Eigen::Index j = 0; j < n; ++j)
    if (!(diagonal[j] > 0.0)) diagonal[j] = smallest;
  return true;
}

Matrix StaticFunctional::state_sensitivity(const Vector& z) {
  forward(z);
  const SparseMatrix mixed = model_.mixed(x_, p_);
  Matrix dx(x_.size(), size());
  Vector unit = Vector::Zero(size());
  for (int j = 0; j < size(); ++j) {
    unit[j] = 1.0;
    dx.col(j) = tangent(parameterization_->jacobian_times(z, unit), mixed);
    unit[j] = 0.0;
  }
  return dx;
}

Vector StaticFunctional::state_vjp(const Vector& z, const Vector& w) {
  forward(z);
  if (w.size() != x_.size())
    throw std::invalid_argument("StaticFunctional::state_vjp: w has " + std::to_string(w.size()) +
                                " entries, the state " + std::to_string(x_.size()));
  return parameterization_->jacobian_transpose_times(z, adjoint_gradient_p(w, Vector::Zero(p_.size())));
}

Vector StaticFunctional::state_jvp(const Vector& z, const Vector& dz) {
  forward(z);
  if (dz.size() != size())
    throw std::invalid_argument("StaticFunctional::state_jvp: dz has " + std::to_string(dz.size()) +
                                " entries, the design " + std::to_string(size()));
  return tangent(parameterization_->jacobian_times(z, dz), product_data(false).mixed);
}

void StaticFunctional::residuals(const Vector& z, Vector& r, Matrix* jacobian) {
  if (!objective_->is_least_squares()) throw std::logic_error("StaticFunctional: the objective has no residual form");
  forward(z);
  SparseMatrix dr_dx, dr_dp;
  objective_->residuals(x_, p_, r, jacobian ? &dr_dx : nullptr, jacobian ? &dr_dp : nullptr);
  if (!jacobian) return;
  const Matrix dx = state_sensitivity(z);
  Matrix dp(p_.size(), size());
  Vector unit = Vector::Zero(size());
  for (int j = 0; j < size(); ++j) {
    unit[j] = 1.0;
    dp.col(j) = parameterization_->jacobian_times(z, unit);
    unit[j] = 0.0;
  }
  *jacobian = dr_dx * dx + dr_dp * dp;
}

}  // namespace tailor
