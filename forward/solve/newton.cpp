#include "forward/solve/newton.hpp"

#include <cmath>
#include <iomanip>
#include <limits>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "forward/core/timing.hpp"
#include "forward/solve/preconditioned_cg.hpp"

namespace tailor {
std::string to_string(NewtonStatus status) {
  switch (status) {
    case NewtonStatus::converged:
      return "converged";
    case NewtonStatus::round_off_floor:
      return "round_off_floor";
    case NewtonStatus::ill_conditioned:
      return "ill_conditioned";
    case NewtonStatus::max_iterations:
      return "max_iterations";
    case NewtonStatus::line_search_failed:
      return "line_search_failed";
    case NewtonStatus::non_finite:
      return "non_finite";
    case NewtonStatus::singular_matrix:
      return "singular_matrix";
  }
  return "unknown";
}

std::string to_string(NewtonHessian hessian) {
  switch (hessian) {
    case NewtonHessian::adaptive:
      return "adaptive";
    case NewtonHessian::exact:
      return "exact";
    case NewtonHessian::projected:
      return "projected";
  }
  return "unknown";
}

std::string to_string(FactorReuse reuse) {
  switch (reuse) {
    case FactorReuse::automatic:
      return "automatic";
    case FactorReuse::on:
      return "on";
    case FactorReuse::off:
      return "off";
  }
  return "unknown";
}

std::string NewtonResult::report() const {
  std::ostringstream s;
  s << "Newton: " << to_string(status) << " after " << iterations << " iterations (" << message << ")\n"
    << std::scientific << std::setprecision(3) << "  residual " << initial_residual << " -> "
    << final_residual << ", energy " << final_energy << "\n";
  double assembly = 0, factor = 0, solve = 0, line = 0;
  for (const auto& it : history) {
    assembly += it.assembly_seconds;
    factor += it.factorization_seconds;
    solve += it.solve_seconds;
    line += it.line_search_seconds;
  }
  const int reused = kept_factor_steps(), cg = cg_iterations();
  int kept = 0;
  for (const auto& it : history) kept += it.kept_constant_factor ? 1 : 0;
  if (kept > 0) s << "  constant Hessian: " << kept << " steps with its kept factorization\n";
  if (reused > 0 || cg > 0)
    s << "  factorizations " << factorizations() << ", steps by CG with a kept factor " << reused << " ("
      << cg << " CG iterations)\n";
  s << std::fixed << std::setprecision(4) << "  time " << total_seconds << " s: analysis " << analysis_seconds
    << ", assembly " << assembly << ", factorization " << factor << ", solve " << solve << ", line search "
    << line << "\n";
  return s.str();
}

int NewtonResult::factorizations() const {
  int n = 0;
  for (const auto& it : history) n += it.factorizations;
  return n;
}

int NewtonResult::kept_factor_steps() const {
  int n = 0;
  for (const auto& it : history) n += it.reused_factorization ? 1 : 0;
  return n;
}

int NewtonResult::cg_iterations() const {
  int n = 0;
  for (const auto& it : history) n += it.cg_iterations;
  return n;
}

bool NewtonSolver::can_precondition() const {
  return factor_is_exact_ && cholesky_.has_factor() && !cholesky_.is_ldlt() &&
         !cholesky_.has_low_rank_update() && cholesky_.rows() == hessian_.rows();
}

bool NewtonSolver::reuse_pays() const {
  // Flops, not timings, so that the choice (and with it the iterates) is the same on every run.
  const double factor = cholesky_.factorization_flops();
  const double solve = 4.0 * cholesky_.factor_nonzeros();
  const double slots = static_cast<double>(assembler_.num_slots());
  return factor > 0.0 && factor >= options_.reuse_min_factor_over_solve * solve &&
         factor >= options_.reuse_min_factor_flops_per_slot * slots;
}

namespace {

// The round-off floor rule (newton.hpp): a residual that stopped decreasing within this factor
// of its componentwise floor estimate is at the floor (the estimate counts the round-off of
// the positions only, not the few more rounding errors of each element's stress).
constexpr double kFloorSlack = 10.0;
// At least one reliable digit: the estimated error below this fraction of the solution's change.
constexpr double kReliableDigit = 0.1;

bool by_parts(const NewtonOptions& options) {
  return options.linear_solver && options.linear_solver->assembles_by_parts();
}

std::vector<const EnergyTerm*> terms_of(const Model& model) {
  std::vector<const EnergyTerm*> terms;
  for (const auto& term : model.terms()) terms.push_back(term.get());
  return terms;
}

}  // namespace

NewtonSolver::NewtonSolver(const Model& model, NewtonOptions options)
    : model_(model),
      options_(options),
      assembler_(model, terms_of(model), /*hessian=*/!by_parts(options_)),
      hessian_(assembler_.hessian_pattern_matrix()) {
  if (by_parts(options_)) share_ = std::make_unique<HessianShare>(model, *options_.linear_solver);
}

void NewtonSolver::assemble_share(const Vector& p, const Vector& y, HessianMode mode) {
  share_assembled_ = share_set_up_ = false;
  share_->assemble(y, p, mode);
  share_p_ = p;
  share_y_ = y;
  share_mode_ = mode;
  share_assembled_ = true;
}

bool NewtonSolver::set_up_share(std::string& message) {
  if (share_set_up_) return true;
  if (!share_assembled_) {
    message = "no Hessian share assembled";
    return false;
  }
  share_set_up_ = options_.linear_solver->setup_share(share_->hessian(), message);
  return share_set_up_;
}

bool NewtonSolver::set_up_exact_share(const Vector& p, const Vector& y, std::string& message) {
  if (!share_) {
    message = "the linear solver does not assemble by parts";
    return false;
  }
  const bool same = share_assembled_ && share_mode_ == HessianMode::exact && share_p_.size() == p.size() &&
                    share_y_.size() == y.size() && share_p_ == p && share_y_ == y;
  if (!same) assemble_share(p, y, HessianMode::exact);
  return set_up_share(message);
}

FactorizationResult NewtonSolver::factorize_hessian(const Vector& p, const Vector& y, HessianMode mode) {
  if (share_)
    throw std::logic_error("NewtonSolver::factorize_hessian: no process holds the whole Hessian in distributed "
                           "assembly (use set_up_exact_share)");
  if (mode == HessianMode::exact && constant_factor_matches(p)) {
    // hessian_ and the factor already hold this (state-independent) Hessian.
    assembled_mode_ = HessianMode::exact;
    factor_matches_hessian_ = true;
    FactorizationResult kept;
    kept.success = kept.kept = true;
    kept.positive_definite = !cholesky_.is_ldlt();
    return kept;
  }
  constant_factor_ = false;
  assembler_.evaluate(y, p, nullptr, nullptr, &hessian_, mode);
  floor_rows_.resize(0);  // solve() estimates the floor from its own exact Hessian again
  assembled_mode_ = mode;
  if (!analyzed_) {
    cholesky_.analyze(hessian_);
    analyzed_ = true;
  }
  const FactorizationResult result = cholesky_.factorize(hessian_);
  factor_p_ = p;
  if (result.success) apply_low_rank(assembler_.low_rank_hessian(y, p, mode));
  factor_is_exact_ = mode == HessianMode::exact && result.success;
  kept_factor_stale_ = false;
  factor_matches_hessian_ = result.success;
  if (factor_is_exact_) remember_constant_factor(p);
  return result;
}

void NewtonSolver::apply_low_rank(const LowRankHessian& low_rank) {
  if (!low_rank.empty()) cholesky_.set_low_rank_update(low_rank.factors, low_rank.core);
}

bool NewtonSolver::constant_factor_matches(const Vector& p) const {
  return !options_.linear_solver && constant_factor_ && options_.keep_constant_factorization && cholesky_.has_factor() &&
         constant_p_.size() == p.size() && constant_p_ == p &&
         constant_revisions_ == model_.hessian_revisions();
}

void NewtonSolver::remember_constant_factor(const Vector& p) {
  constant_factor_ = options_.keep_constant_factorization && model_.hessian_is_constant() &&
                     !cholesky_.has_low_rank_update();
  if (!constant_factor_) return;
  constant_p_ = p;
  constant_revisions_ = model_.hessian_revisions();
}

HessianMode NewtonSolver::choose_mode(const HessianChoice& choice) const {
  switch (options_.hessian) {
    case NewtonHessian::exact:
      return HessianMode::exact;
    case NewtonHessian::projected:
      return HessianMode::projected;
    case NewtonHessian::adaptive:
      break;
  }
  return choice.projected_left > 0 ? HessianMode::projected : HessianMode::exact;
}

double NewtonSolver::estimate_floor_rows(double h_norm, double max_diagonal, double min_diagonal) {
  floor_rows_ = Vector::Constant(hessian_.rows() > 0 ? hessian_.rows() : model_.elimination().num_free(),
                                 std::numeric_limits<double>::epsilon() * h_norm);
  return min_diagonal > 0.0 && std::isfinite(min_diagonal) ? max_diagonal / min_diagonal
                                                           : std::numeric_limits<double>::infinity();
}

double NewtonSolver::estimate_floor_rows() {
  // The symmetric matrix is stored as its upper triangle: each off-diagonal entry counts in its
  // row and in its column.
  floor_rows_ = Vector::Zero(hessian_.rows());
  double max_diagonal = 0.0, min_diagonal = std::numeric_limits<double>::infinity();
  for (int j = 0; j < hessian_.outerSize(); ++j)
    for (SparseMatrix::InnerIterator e(hessian_, j); e; ++e) {
      floor_rows_[e.row()] += std::abs(e.value());
      if (e.row() != j) {
        floor_rows_[j] += std::abs(e.value());
      } else {
        max_diagonal = std::max(max_diagonal, std::abs(e.value()));
        min_diagonal = std::min(min_diagonal, std::abs(e.value()));
      }
    }
  floor_rows_ *= std::numeric_limits<double>::epsilon();
  return min_diagonal > 0.0 && std::isfinite(min_diagonal) ? max_diagonal / min_diagonal
                                                           : std::numeric_limits<double>::infinity();
}

std::pair<double, double> NewtonSolver::floor_ratio(const Vector& gradient, const Vector& x) const {
  if (floor_rows_.size() != gradient.size()) return {std::numeric_limits<double>::infinity(), 0.0};
  const double x_scale = 1.0 + x.lpNorm<Eigen::Infinity>();
  double ratio = 0.0;
  for (Eigen::Index i = 0; i < gradient.size(); ++i) {
    const double g = std::abs(gradient[i]);
    if (g == 0.0) continue;
    // A row without stiffness has no round-off to hide a force behind: never at the floor.
    const double f = floor_rows_[i] * x_scale;
    ratio = std::max(ratio, f > 0.0 ? g / f : std::numeric_limits<double>::infinity());
  }
  return {ratio, floor_rows_.norm() * x_scale};
}

double NewtonSolver::error_estimate(const Vector& gradient, const NewtonIteration& last) {
  // The next Newton step is the iterate's error to first order (x* - x = -H^-1 g); at the floor
  // g is round-off, and the step is that round-off propagated through the inverse stiffness.
  if (!options_.linear_solver && factor_is_exact_ && cholesky_.has_factor() && cholesky_.rows() == gradient.size()) {
    const Vector dy = cholesky_.solve(Vector(-gradient));
    if (dy.allFinite()) return model_.elimination().expand_direction(dy).lpNorm<Eigen::Infinity>();
  }
  // Another solver (or a projected or shifted factor): the last step's direction, taken at an
  // iterate that was at the floor as well.
  return last.step_length > 0.0 ? last.step_norm / last.step_length : std::numeric_limits<double>::infinity();
}

bool NewtonSolver::kept_factor_step(const Vector& gradient, double residual, double scale, double target,
                                    NewtonIteration& it, Vector& dy) {
  // Inexact Newton (Dembo, Eisenstat & Steihaug 1982): the step solves H dy = -g to a
  // relative residual eta. Aim for eta = min(0.1, ||g|| / scale), Eisenstat & Walker's (1996)
  // quadratic forcing, so that the Newton iterations are as few as with exact solves (an
  // iteration's assembly and line search cost more than a CG iteration), but never tighter
  // than half of what the convergence target needs. When the kept factor is too poor a
  // preconditioner to get there within the CG cap, a step with eta <= 0.1 is still taken (it
  // converges, only more slowly); a worse one makes this iteration factorize.
  const auto t0 = Clock::now();
  const double eta = std::min(0.1, std::max(residual / scale, 0.5 * target / residual));
  const PcgResult cg =
      preconditioned_cg(hessian_, cholesky_, Vector(-gradient), eta, options_.reuse_max_cg_iterations, dy);
  it.solve_seconds += seconds_since(t0);
  it.cg_iterations = cg.iterations;
  it.cg_relative_residual = cg.relative_residual;
  // A factor that no longer gets CG to eta within the cap has gone stale: the step is still
  // taken (if eta <= 0.1), but the next iteration factorizes afresh.
  kept_factor_stale_ = !cg.converged;
  return cg.relative_residual <= 0.1 && dy.allFinite() && dy.dot(gradient) < 0.0;
}

std::string NewtonSolver::factorized_step(const Vector& p, const Vector& y, const Vector& gradient,
                                          HessianMode& mode, HessianChoice& choice,
                                          const LowRankHessian& low_rank, NewtonIteration& it, Vector& dy) {
  auto t0 = Clock::now();
  factor_is_exact_ = false;  // until a factorization below is known to be of the exact Hessian
  constant_factor_ = false;
  kept_factor_stale_ = false;
  FactorizationResult fact = cholesky_.factorize(hessian_);
  factor_p_ = p;
  ++it.factorizations;
  it.factorization_seconds = seconds_since(t0);
  if (mode == HessianMode::exact && !fact.positive_definite && model_.hessian_is_constant()) {
    // A constant Hessian of our terms is positive semidefinite by construction, and definite
    // once the supports hold the body: a failed Cholesky means it is singular or beyond double
    // precision. Shifting it would only creep towards a wrong answer.
    ill_conditioned_ = true;
    std::ostringstream why;
    why << std::scientific << std::setprecision(1)
        << "the stiffness matrix is not positive definite in double precision although every term is "
           "quadratic: "
           "it is singular (a free motion) or too ill-conditioned (condition number at least "
        << condition_hint_ << "; a contrast of moduli?)";
    return why.str();
  }
  if (choice.projected_left > 0) --choice.projected_left;
  if (mode == HessianMode::exact && fact.positive_definite) choice.projected_backoff = 1;
  if (options_.hessian == NewtonHessian::adaptive && mode == HessianMode::exact && !fact.positive_definite) {
    // Indefinite exact Hessian: use the projected one now and in the next iteration.
    t0 = Clock::now();
    assembler_.evaluate(y, p, nullptr, nullptr, &hessian_, HessianMode::projected);
    it.assembly_seconds += seconds_since(t0);
    mode = assembled_mode_ = HessianMode::projected;
    // Back off exponentially: a failed exact attempt costs one factorization, so after
    // consecutive failures wait 1, 2, 4, ... iterations before trying again.
    choice.projected_left = choice.projected_backoff;
    choice.projected_backoff = std::min(2 * choice.projected_backoff, 16);
    t0 = Clock::now();
    fact = cholesky_.factorize(hessian_);
    ++it.factorizations;
    it.factorization_seconds += seconds_since(t0);
  }
  it.used_projected = mode == HessianMode::projected;
  double shift = 0.0;
  for (int attempt = 0;; ++attempt) {
    if (fact.success) {
      apply_low_rank(low_rank);
      t0 = Clock::now();
      dy = cholesky_.solve(Vector(-gradient));
      it.solve_seconds += seconds_since(t0);
      if (dy.allFinite() && dy.dot(gradient) < 0.0) break;
    }
    if (attempt == 30)
      return "no descent direction at iteration " + std::to_string(it.iteration) + ": " + fact.message;
    // Levenberg-style diagonal shift, relative to the largest diagonal entry.
    double max_diag = 0.0;
    for (int j = 0; j < hessian_.outerSize(); ++j)
      max_diag = std::max(max_diag, std::abs(hessian_.coeff(j, j)));
    const double next = shift == 0.0 ? 1e-8 * std::max(max_diag, 1e-300) : 10.0 * shift;
    for (int j = 0; j < hessian_.outerSize(); ++j) hessian_.coeffRef(j, j) += next - shift;
    shift = next;
    t0 = Clock::now();
    fact = cholesky_.factorize(hessian_);
    ++it.factorizations;
    it.factorization_seconds += seconds_since(t0);
  }
  it.used_ldlt = cholesky_.is_ldlt();
  factor_is_exact_ = mode == HessianMode::exact && shift == 0.0;
  factor_matches_hessian_ = true;
  if (factor_is_exact_) remember_constant_factor(p);
  return {};
}

std::string NewtonSolver::external_step(const Vector& p, const Vector& y, const Vector& gradient,
                                        NewtonIteration& it, Vector& dy) {
  LinearSolver& solver = *options_.linear_solver;
  if (!assembler_.low_rank_hessian(y, p, assembled_mode_).empty())
    return "the linear solver '" + solver.name() + "' does not support terms with low-rank Hessian parts";
  factor_is_exact_ = false;
  factor_matches_hessian_ = false;
  constant_factor_ = false;
  auto t0 = Clock::now();
  std::string message;
  const bool ready = share_ ? set_up_share(message) : solver.setup(hessian_, message);
  ++it.factorizations;
  it.factorization_seconds = seconds_since(t0);
  if (!ready) return "linear solver '" + solver.name() + "' set-up failed at iteration " + std::to_string(it.iteration) + ": " + message;
  t0 = Clock::now();
  const LinearSolveStats stats = solver.solve(Vector(-gradient), 0.0, dy);
  it.solve_seconds = seconds_since(t0);
  it.cg_iterations = stats.iterations;
  it.cg_relative_residual = stats.relative_residual;
  it.used_projected = assembled_mode_ == HessianMode::projected;
  if (!stats.converged)
    return "linear solver '" + solver.name() + "' did not converge at iteration " + std::to_string(it.iteration) + ": " + stats.message;
  if (!dy.allFinite() || dy.dot(gradient) >= 0.0)
    return "linear solver '" + solver.name() + "' gave no descent direction at iteration " +
           std::to_string(it.iteration) + " (the Hessian is not positive definite?)";
  return {};
}

bool NewtonSolver::line_search(const Vector& p, Vector& y, const Vector& dy, double energy,
                               const Vector& gradient, double residual, NewtonIteration& it,
                               double& accepted_energy, Vector& accepted_gradient, bool& accepted_evaluated) {
  const auto t0 = Clock::now();
  accepted_evaluated = false;
  const Vector dx = model_.elimination().expand_direction(dy);
  double alpha = std::min(1.0, model_.max_step(model_.state(y, p), dx));
  const double slope = gradient.dot(dy);
  const double round_off = 64.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(energy), 1e-300);
  // dy = -H^-1 g with H the exact Hessian: CHOLMOD's unshifted factor of it, not CG's step.
  const bool exact_newton =
      !options_.linear_solver && factor_is_exact_ && !it.reused_factorization && !it.used_projected;
  bool accepted = false;
  if (it.kept_constant_factor && alpha == 1.0 && slope < 0.0 && model_.hessian_is_constant()) {
    // The energy is quadratic with the factorized Hessian H, and dy = -H^-1 g: the full step
    // lowers it by exactly -g.dy / 2 > 0, so evaluating the energy there would only confirm the
    // Armijo condition. The next iteration's residual still checks the step.
    y += dy;
    it.line_search_seconds = seconds_since(t0);
    it.step_length = 1.0;
    it.step_norm = dx.lpNorm<Eigen::Infinity>();
    return true;
  }
  for (int ls = 0; ls <= options_.max_line_search_steps; ++ls, alpha *= 0.5) {
    it.line_search_steps = ls;
    const Vector trial = y + alpha * dy;
    double trial_energy = 0.0;
    // Most steps are accepted at the first trial: its gradient then serves the next iteration.
    const bool with_gradient = ls == 0;
    Vector trial_gradient;
    assembler_.evaluate(trial, p, &trial_energy, with_gradient ? &trial_gradient : nullptr, nullptr);
    if (!std::isfinite(trial_energy)) continue;
    if (trial_energy <= energy + options_.armijo * alpha * slope) {
      accepted = true;
    } else if (std::abs(trial_energy - energy) <= round_off) {
      // Energy differences are at round-off: judge the step by the residual instead.
      if (!with_gradient) assembler_.evaluate(trial, p, nullptr, &trial_gradient, nullptr);
      accepted = trial_gradient.norm() < residual;
    } else if (ls == 0 && exact_newton && std::abs(slope) <= 1e-6 * std::abs(energy) &&
               trial_gradient.norm() < residual) {
      // The full step's predicted decrease (-slope / 2 for a step of the exact Hessian; an
      // inexact step's differs) is a millionth of the energy: it may be below the energy's own
      // round-off, which a sum of element energies that each cancel O(modulus) terms (a stable
      // Neo-Hookean at small strain) makes far larger than 64 eps |E|. Measure that round-off:
      // the energy a thousandth of the way along the step should differ from E by a thousandth
      // of the slope; what differs more is noise.
      // When the noise hides the predicted decrease and the step changed the energy by no more
      // than the noise, judge the step by the residual, which it lowered.
      double probe_energy = 0.0;
      assembler_.evaluate(Vector(y + 1e-3 * alpha * dy), p, &probe_energy, nullptr, nullptr);
      const double noise = std::abs(probe_energy - energy - 1e-3 * alpha * slope);
      accepted = std::isfinite(noise) && 0.5 * std::abs(alpha * slope) <= 2.0 * noise &&
                 trial_energy - energy <= 2.0 * noise;
    }
    if (accepted) {
      y = trial;
      if (with_gradient) {
        accepted_energy = trial_energy;
        accepted_gradient = std::move(trial_gradient);
        accepted_evaluated = true;
      }
      break;
    }
  }
  it.line_search_seconds = seconds_since(t0);
  it.step_length = accepted ? alpha : 0.0;
  it.step_norm = accepted ? alpha * dx.lpNorm<Eigen::Infinity>() : 0.0;
  return accepted;
}

NewtonResult NewtonSolver::solve(const Vector& p, Vector& y) {
  const auto t_start = Clock::now();
  NewtonResult result;
  const Elimination& elim = model_.elimination();
  if (y.size() != elim.num_free()) {
    result.status = NewtonStatus::non_finite;
    result.message = "initial guess has " + std::to_string(y.size()) + " unknowns, the model " +
                     std::to_string(elim.num_free());
    return result;
  }
  // (A linear solver of its own needs no CHOLMOD analysis; factorize_hessian does it on demand.)
  if (!analyzed_ && !options_.linear_solver) {
    const auto t0 = Clock::now();
    cholesky_.analyze(hessian_);
    analyzed_ = true;
    result.analysis_seconds = seconds_since(t0);
  }

  auto finish = [&](NewtonStatus status, std::string message) {
    result.status = status;
    result.message = std::move(message);
    result.total_seconds = seconds_since(t_start);
    return result;
  };

  double energy = 0.0;
  Vector gradient;
  // The line search's energy and gradient at the accepted point, when it evaluated them there.
  double carried_energy = 0.0;
  Vector carried_gradient;
  bool carried = false;
  HessianChoice choice;
  const Vector y_start = y;  // solution_change is measured from here
  bool started_at_floor = false;  // the start's residual was within its round-off floor
  bool cg_in_this_solve = true;  // FactorReuse::automatic: no CG step of this solve has stalled
  for (int k = 0;; ++k) {
    NewtonIteration it;
    it.iteration = k;
    HessianMode mode = choose_mode(choice);
    // A kept factor of the constant Hessian at these parameters makes assembling it again
    // (and factorizing it) unnecessary.
    const bool kept_constant = mode == HessianMode::exact && constant_factor_matches(p);
    auto t0 = Clock::now();
    // after_step may have changed the terms' settings: everything is evaluated afresh then.
    if (share_) {
      // Distributed assembly: energy and gradient replicated, the Hessian by shares.
      if (carried && !options_.after_step) {
        energy = carried_energy;
        gradient.swap(carried_gradient);
      } else {
        assembler_.evaluate(y, p, &energy, &gradient, nullptr);
      }
      assemble_share(p, y, mode);
    } else if (carried && !options_.after_step) {
      energy = carried_energy;
      gradient.swap(carried_gradient);
      if (!kept_constant) assembler_.evaluate(y, p, nullptr, nullptr, &hessian_, mode);
    } else {
      assembler_.evaluate(y, p, &energy, &gradient, kept_constant ? nullptr : &hessian_, mode);
    }
    carried = false;
    it.assembly_seconds = seconds_since(t0);
    if (!kept_constant) {
      assembled_mode_ = mode;
      factor_matches_hessian_ = false;
    } else {
      assembled_mode_ = HessianMode::exact;
      factor_matches_hessian_ = true;
    }
    const double residual = gradient.norm();
    it.energy = energy;
    it.residual = residual;
    if (k == 0) result.initial_residual = residual;
    result.final_residual = residual;
    result.final_energy = energy;
    result.iterations = k;
    if (!std::isfinite(energy) || !std::isfinite(residual))
      return finish(NewtonStatus::non_finite,
                    "energy or gradient is not finite at iteration " + std::to_string(k));

    const double scale = std::max(result.initial_residual, options_.reference_residual);
    const double target = std::max(options_.relative_tolerance * scale, options_.absolute_tolerance);
    if (residual <= target) return finish(NewtonStatus::converged, "residual below tolerance");
    // The floor's row sums come from each exact Hessian assembled (a kept constant one is the
    // same matrix); its size scales with the current coordinates.
    if (mode == HessianMode::exact && (!kept_constant || floor_rows_.size() != gradient.size())) {
      if (!share_) {
        floor_condition_ = estimate_floor_rows();
      } else {
        // From the solver, which holds the summed shares (a failed set-up is reported by the step).
        std::string ignored;
        double h_norm = 0.0, max_diagonal = 0.0, min_diagonal = 0.0;
        if (set_up_share(ignored) && options_.linear_solver->matrix_norms(h_norm, max_diagonal, min_diagonal))
          floor_condition_ = estimate_floor_rows(h_norm, max_diagonal, min_diagonal);
      }
    }
    const Vector x = model_.state(y, p);
    if (floor_rows_.size() == gradient.size()) {
      std::tie(result.floor_ratio, result.residual_floor) = floor_ratio(gradient, x);
      result.condition_estimate = floor_condition_;
    }
    // What a floor must be below for the residual alone to certify the solution: sqrt(relative
    // tolerance) of the load scale, which an absolute tolerance implies too (absolute / relative,
    // e.g. when a warm start from a ramped equilibrium makes ||g_0|| tiny).
    const double load_scale = std::max(scale, options_.absolute_tolerance / options_.relative_tolerance);
    const double accurate = std::sqrt(options_.relative_tolerance) * load_scale;
    std::ostringstream why;
    why << std::scientific << std::setprecision(2);
    // A start within its floor may still be far from the equilibrium where the stiffness is
    // ill-conditioned (a load on a stiff block held by a soft support is below the block's
    // round-off, yet moves it): the first Newton step decides, below.
    const bool start_at_floor = k == 0 && result.residual_floor > 0.0 && result.floor_ratio <= 1.0;
    if (start_at_floor) started_at_floor = true;
    // At the floor: has the answer digits? (See the top of newton.hpp.)
    auto at_floor = [&](const NewtonIteration& last, bool below_floor_estimate) {
      why << "residual " << residual << " at its round-off floor (estimated " << result.residual_floor
          << ", componentwise ratio " << result.floor_ratio << "; requested " << target << ")";
      if (residual <= accurate) return finish(NewtonStatus::round_off_floor, why.str());
      if (!below_floor_estimate) {
        // Refinement with the factor of a constant Hessian stalled above the floor: the
        // factorization's solves have no digits left.
        why << ": refinement with the stiffness factorization stalls above the floor, the "
            << "stiffness matrix is too ill-conditioned for double precision (condition number at least "
            << result.condition_estimate << "; a contrast of moduli?), the solution has no reliable digits";
        return finish(NewtonStatus::ill_conditioned, why.str());
      }
      result.accuracy = error_estimate(gradient, last);
      result.solution_change = model_.elimination().expand_direction(y - y_start).lpNorm<Eigen::Infinity>();
      const double storage = 100.0 * std::numeric_limits<double>::epsilon() * (1.0 + x.lpNorm<Eigen::Infinity>());
      why << ", " << residual / scale << " of the initial residual; estimated error of the solution "
          << result.accuracy << " against a change of " << result.solution_change;
      if (result.accuracy < kReliableDigit * result.solution_change || result.accuracy <= storage)
        return finish(NewtonStatus::round_off_floor, why.str());
      if (started_at_floor && result.condition_estimate * std::numeric_limits<double>::epsilon() < 1.0) {
        // The start's residual was within its floor, and the steps from it have no digits: the
        // start is as good an answer as double precision gives (a sliver element at rest, its
        // residual pure round-off). Where the diagonal alone shows the stiffness beyond double
        // precision, a load below the round-off is the likelier reading: ill_conditioned below.
        y = y_start;
        // hessian() is the Hessian at the returned iterate after a converged solve (the adjoint
        // relies on it); the factor is of another iterate's.
        if (share_) {
          assemble_share(p, y, HessianMode::exact);
        } else {
          assembler_.evaluate(y, p, nullptr, nullptr, &hessian_, HessianMode::exact);
          assembled_mode_ = HessianMode::exact;
        }
        factor_matches_hessian_ = false;
        result.accuracy = result.solution_change;
        result.final_residual = result.initial_residual;
        result.final_energy = result.history.front().energy;
        result.iterations = 0;
        std::ostringstream start;
        start << std::scientific << std::setprecision(2) << "the start is in equilibrium to round-off (residual "
              << result.initial_residual << "); Newton steps from it have no reliable digits (estimated error "
              << result.accuracy << ")";
        return finish(NewtonStatus::round_off_floor, start.str());
      }
      why << ": the stiffness matrix is too ill-conditioned for double precision (condition number at least "
          << result.condition_estimate << "; a contrast of moduli?), the solution has no reliable digits";
      return finish(NewtonStatus::ill_conditioned, why.str());
    };
    if (k > 0) {
      const NewtonIteration& last = result.history.back();
      const double x_scale = 1.0 + x.lpNorm<Eigen::Infinity>();
      const bool full_step = last.step_length == 1.0;
      if (full_step && last.step_norm <= options_.step_tolerance * x_scale && residual <= accurate)
        return finish(NewtonStatus::converged, "step at round-off level");
      // At the floor: within it, or within floor_slack of it and no longer decreasing.
      const bool stagnant = residual > 0.5 * last.residual;
      const bool near_floor =
          result.residual_floor > 0.0 &&
          (result.floor_ratio <= 1.0 || (stagnant && result.floor_ratio <= kFloorSlack));
      // Or a full step of an exact factorization that did not halve the residual (quadratic
      // convergence has stopped). With a constant Hessian every step after the first is
      // iterative refinement with the same factor, and the energy is quadratic: a step of any
      // length that does not halve the residual means the residual is at its floor or the
      // factor's solves have no digits left (a line search that shortens such steps only hides
      // it).
      const bool exact_step = (last.factorizations == 1 && !last.used_projected) || last.kept_constant_factor;
      const bool refinement = exact_step && model_.hessian_is_constant();
      const bool stalled = (full_step || refinement) && exact_step && stagnant;
      if (near_floor || (stalled && (residual <= accurate || refinement))) return at_floor(last, near_floor);
    }
    if (k == options_.max_iterations)
      return finish(NewtonStatus::max_iterations, "iteration limit " + std::to_string(k) + " reached");

    Vector dy;
    if (kept_constant) {
      t0 = Clock::now();
      dy = cholesky_.solve(Vector(-gradient));
      it.solve_seconds = seconds_since(t0);
      it.kept_constant_factor = true;
      it.used_ldlt = cholesky_.is_ldlt();
    } else if (options_.linear_solver) {
      const std::string error = external_step(p, y, gradient, it, dy);
      if (!error.empty()) return finish(NewtonStatus::singular_matrix, error);
    } else {
      // Terms' low-rank Hessian parts go on top of the sparse factor (Woodbury); CG with the
      // kept factor sees only the sparse part, so it is tried only without them.
      const LowRankHessian low_rank = assembler_.low_rank_hessian(y, p, mode);
      bool try_cg = options_.reuse_factorization == FactorReuse::on;
      if (options_.reuse_factorization == FactorReuse::automatic && cg_in_this_solve) {
        // Converging: a first iteration next to the kept factor's state, or a full step that at
        // least halved the residual. A CG step that did not ends CG for this solve.
        const NewtonIteration* last = k > 0 ? &result.history.back() : nullptr;
        const bool converging = !last || (last->step_length == 1.0 && residual <= 0.5 * last->residual);
        if (last && last->reused_factorization && !converging) cg_in_this_solve = false;
        const bool same_parameters = options_.reuse_across_parameters ||
                                     (factor_p_.size() == p.size() && factor_p_ == p);
        try_cg = cg_in_this_solve && converging && same_parameters && reuse_pays();
      }
      if (try_cg && low_rank.empty() && mode == HessianMode::exact && !kept_factor_stale_ && can_precondition())
        it.reused_factorization = kept_factor_step(gradient, residual, scale, target, it, dy);
      if (!it.reused_factorization) {
        condition_hint_ = result.condition_estimate;
        ill_conditioned_ = false;
        const std::string error = factorized_step(p, y, gradient, mode, choice, low_rank, it, dy);
        if (!error.empty())
          return finish(ill_conditioned_ ? NewtonStatus::ill_conditioned : NewtonStatus::singular_matrix,
                        error);
      }
    }

    if (start_at_floor) {
      // In equilibrium to round-off when the Newton step would not move the state beyond the
      // precision its coordinates are stored to.
      const double step = model_.elimination().expand_direction(dy).lpNorm<Eigen::Infinity>();
      if (step <= 100.0 * std::numeric_limits<double>::epsilon() * (1.0 + x.lpNorm<Eigen::Infinity>())) {
        why << "the start is in equilibrium to round-off (residual " << residual << ", floor about "
            << result.residual_floor << ", Newton step " << step << ")";
        result.accuracy = step;
        return finish(NewtonStatus::round_off_floor, why.str());
      }
    }
    if (options_.direction_converged &&
        options_.direction_converged(model_.state(y, p), model_.elimination().expand_direction(dy)))
      return finish(NewtonStatus::converged, "Newton direction within the caller's tolerance");
    const bool accepted =
        line_search(p, y, dy, energy, gradient, residual, it, carried_energy, carried_gradient, carried);
    result.history.push_back(it);
    // No decrease left to find within floor_slack of the floor: the residual is at its floor.
    if (!accepted && result.residual_floor > 0.0 && result.floor_ratio <= kFloorSlack) {
      it.step_length = 1.0;  // for error_estimate's fallback: the direction just computed
      it.step_norm = model_.elimination().expand_direction(dy).lpNorm<Eigen::Infinity>();
      return at_floor(it, true);
    }
    if (!accepted)
      return finish(NewtonStatus::line_search_failed,
                    "line search found no decrease at iteration " + std::to_string(k) + " after " +
                        std::to_string(options_.max_line_search_steps) + " halvings");
    if (options_.after_step) options_.after_step(model_.state(y, p));
    if (options_.progress) {
      *options_.progress << std::scientific << std::setprecision(3) << "  newton " << std::setw(3) << k
                         << "  E " << std::setw(11) << energy << "  |g| " << residual << "  alpha "
                         << std::defaultfloat << it.step_length << (it.used_projected ? "  projected" : "")
                         << (it.reused_factorization ? "  cg " + std::to_string(it.cg_iterations)
                                                     : std::string())
                         << (it.kept_constant_factor ? "  kept factor" : "")
                         << (it.used_ldlt ? "  (LDL^T)" : "") << "\n";
    }
  }
}

}  // namespace tailor
