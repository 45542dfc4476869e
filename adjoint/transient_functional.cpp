#include "adjoint/transient_functional.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <stdexcept>

#include "forward/core/timing.hpp"
#include "forward/solve/preconditioned_cg.hpp"

namespace tailor {
namespace {

double state_megabytes(const DynamicState& s) {
  const auto doubles = s.y.size() + s.x.size() + s.v.size() + s.x_previous.size() + s.v_previous.size() +
                       s.carried_force.size();
  return 8.0 * static_cast<double>(doubles) / (1024.0 * 1024.0);
}

}  // namespace

// Adjoints (dJ/d.) of the parts of one DynamicState.
struct TransientFunctional::Adjoint {
  Vector x, v, x_previous, v_previous, force;
  explicit Adjoint(Eigen::Index n)
      : x(Vector::Zero(n)),
        v(Vector::Zero(n)),
        x_previous(Vector::Zero(n)),
        v_previous(Vector::Zero(n)),
        force(Vector::Zero(n)) {}
};

TransientFunctional::TransientFunctional(TimeIntegrator& integrator, ParameterizationPtr parameterization,
                                         TrajectoryObjectivePtr objective, Vector initial_positions,
                                         Vector initial_velocities, TransientFunctionalOptions options)
    : integrator_(integrator),
      parameterization_(std::move(parameterization)),
      objective_(std::move(objective)),
      x0_(std::move(initial_positions)),
      v0_(std::move(initial_velocities)),
      options_(options) {
  if (!parameterization_ || !objective_)
    throw std::invalid_argument("TransientFunctional: parameterization and objective are required");
  const int n = integrator_.model().num_dofs();
  if (x0_.size() != n || v0_.size() != n)
    throw std::invalid_argument("TransientFunctional: initial positions and velocities must have " +
                                std::to_string(n) + " entries");
  if (options_.steps < 1) throw std::invalid_argument("TransientFunctional: at least one step is required");
  if (options_.checkpoint_interval < 0)
    throw std::invalid_argument("TransientFunctional: negative checkpoint interval");
  if (parameterization_->num_params() != num_extended_params())
    throw std::invalid_argument("TransientFunctional: the parameterization produces " +
                                std::to_string(parameterization_->num_params()) + " parameters, expected " +
                                std::to_string(num_extended_params()) + " (model parameters" +
                                (options_.design_initial_positions ? " + initial positions" : "") +
                                (options_.design_initial_velocities ? " + initial velocities" : "") + ")");
  hessian_ = integrator_.newton().assembler().hessian_pattern_matrix();
}

int TransientFunctional::num_extended_params() const {
  const int n = integrator_.model().num_dofs();
  return integrator_.model().parameter_layout().size() + (options_.design_initial_positions ? n : 0) +
         (options_.design_initial_velocities ? n : 0);
}

void TransientFunctional::store(const DynamicState& state) {
  const int k = options_.checkpoint_interval;
  if (k <= 1) {
    stored_.push_back(state);
  } else if (state.step % k == 0 && state.step < options_.steps) {
    stored_.push_back(state);
    tail_.clear();
  } else {
    tail_.push_back(state);
  }
  const int count = static_cast<int>(stored_.size() + tail_.size());
  if (count > statistics_.stored_states_peak) {
    statistics_.stored_states_peak = count;
    statistics_.stored_megabytes_peak = count * state_megabytes(state);
  }
}

void TransientFunctional::forward(const Vector& z) {
  if (z.size() != size())
    throw std::invalid_argument("TransientFunctional: z has " + std::to_string(z.size()) +
                                " entries, expected " + std::to_string(size()));
  if (have_state_ && z == z_) return;
  have_state_ = false;
  const auto t0 = Clock::now();
  const Vector P = parameterization_->apply(z);
  const int np = integrator_.model().parameter_layout().size(), n = integrator_.model().num_dofs();
  p_ = P.head(np);
  int offset = np;
  x_init_ = options_.design_initial_positions ? Vector(P.segment(offset, n)) : x0_;
  if (options_.design_initial_positions) offset += n;
  v_init_ = options_.design_initial_velocities ? Vector(P.segment(offset, n)) : v0_;

  {
    // The linear solver's figures are of the last backward pass; keep them over value() calls.
    TransientStatistics fresh;
    fresh.linear_solver_solves = statistics_.linear_solver_solves;
    fresh.linear_solver_iterations = statistics_.linear_solver_iterations;
    fresh.last_linear_solve = statistics_.last_linear_solve;
    statistics_ = fresh;
  }
  statistics_.steps = options_.steps;
  stored_.clear();
  tail_.clear();
  step_hessians_.assign(options_.steps + 1, Vector());
  step_hessian_megabytes_ = 0.0;
  newton_factor_step_ = -1;
  const SparseCholesky& newton_factor = integrator_.newton().factorization();
  const long factorizations0 = newton_factor.numeric_factorizations(), solves0 = newton_factor.back_solves();
  DynamicState state = integrator_.initial_state(x_init_, v_init_, p_);
  value_ = objective_->value(0, state.x, state.v, p_);
  store(state);
  for (int step = 0; step < options_.steps; ++step) {
    const NewtonResult r = integrator_.step(state, p_);
    ++statistics_.forward_steps;
    statistics_.newton_iterations += r.iterations;
    if (!r.converged())
      throw EvaluationError("time step " + std::to_string(step + 1) + " failed: " + to_string(r.status) +
                            " (" + r.message + ")");
    if (r.factorizations() > 0) newton_factor_step_ = state.step;
    keep_step_hessian(state.step);
    value_ += objective_->value(state.step, state.x, state.v, p_);
    store(state);
  }
  statistics_.forward_factorizations = newton_factor.numeric_factorizations() - factorizations0;
  statistics_.forward_back_solves = newton_factor.back_solves() - solves0;
  statistics_.forward_seconds = seconds_since(t0);
  counters_.forward_solves += options_.steps;
  counters_.forward_seconds += statistics_.forward_seconds;
  ++counters_.evaluations;
  z_ = z;
  have_state_ = true;
}

double TransientFunctional::value(const Vector& z) {
  forward(z);
  return value_;
}

void TransientFunctional::add_objective_gradient(const DynamicState& s, Adjoint& adjoint,
                                                 Vector& gradient_p) const {
  objective_->add_gradient(s.step, s.x, s.v, p_, adjoint.x, adjoint.v, gradient_p);
}

void TransientFunctional::keep_step_hessian(int step) {
  // Newton's last assembly of a converged solve is the Hessian at the returned iterate
  // (NewtonSolver::hessian()); only an exact one of the step's own settings is the adjoint's.
  NewtonSolver& newton = integrator_.newton();
  if (options_.stored_hessian_megabytes <= 0.0 || !options_.reuse_factorizations || step < 0 ||
      step >= static_cast<int>(step_hessians_.size()) || newton.options().linear_solver ||
      newton.assembles_by_parts() || newton.options().after_step ||
      integrator_.model().hessian_is_constant() || newton.assembled_mode() != HessianMode::exact)
    return;
  const SparseMatrix& H = newton.hessian();
  if (H.rows() != hessian_.rows() || H.nonZeros() != hessian_.nonZeros() || !H.isCompressed()) return;
  if (step_hessians_[step].size() != 0) return;  // kept by the forward pass, now recomputed
  const double megabytes = 8.0 * static_cast<double>(H.nonZeros()) / (1024.0 * 1024.0);
  if (step_hessian_megabytes_ + megabytes > options_.stored_hessian_megabytes) return;
  step_hessians_[step] = Eigen::Map<const Vector>(H.valuePtr(), H.nonZeros());
  step_hessian_megabytes_ += megabytes;
  statistics_.stored_hessian_megabytes_peak =
      std::max(statistics_.stored_hessian_megabytes_peak, step_hessian_megabytes_);
}

bool TransientFunctional::take_stored_hessian(int step, bool release) {
  if (step < 0 || step >= static_cast<int>(step_hessians_.size())) return false;
  Vector& values = step_hessians_[step];
  if (values.size() == 0 || values.size() != hessian_.nonZeros()) return false;
  Eigen::Map<Vector>(hessian_.valuePtr(), hessian_.nonZeros()) = values;
  ++statistics_.stored_hessians_used;
  if (!release) return true;  // the tangent pass: the backward pass may still want it
  step_hessian_megabytes_ -= 8.0 * static_cast<double>(values.size()) / (1024.0 * 1024.0);
  Vector().swap(values);  // each is used once: free it for the recomputed segments' copies
  return true;
}

Vector TransientFunctional::solve_step(const Vector& rhs, int step) {
  // Low-rank Hessian parts (LowRankHessian) are not in hessian_: factorize with a Woodbury update.
  if (options_.reuse_factorizations && low_rank_.empty()) {
    // The exact LL^T factor nearest in time preconditions CG: the backward pass's own, or
    // Newton's last one (made at an iterate of step newton_factor_step_; -1: before this pass).
    auto usable = [this](const SparseCholesky& f) {
      return f.has_factor() && !f.is_ldlt() && !f.has_low_rank_update() && f.rows() == hessian_.rows();
    };
    NewtonSolver& newton = integrator_.newton();
    const SparseCholesky* own = have_factor_ && usable(factor_) ? &factor_ : nullptr;
    const SparseCholesky* newtons =
        newton.factorization_is_exact() && usable(newton.factorization()) ? &newton.factorization() : nullptr;
    const SparseCholesky* preconditioner = own ? own : newtons;
    if (own && newtons && newton_factor_step_ >= 0 &&
        std::abs(newton_factor_step_ - step) < std::abs(factor_step_ - step))
      preconditioner = newtons;
    if (preconditioner) {
      const auto t0 = Clock::now();
      Vector v;
      const PcgResult cg = preconditioned_cg(
          hessian_, *preconditioner, rhs, options_.linear_relative_tolerance, options_.max_cg_iterations, v);
      statistics_.adjoint_solve_seconds += seconds_since(t0);
      if (cg.converged) {
        ++statistics_.cg_solves;
        statistics_.cg_iterations += cg.iterations;
        statistics_.max_preconditioner_residual =
            std::max(statistics_.max_preconditioner_residual, cg.initial_relative_residual);
        return v;
      }
    }
  }
  auto t0 = Clock::now();
  if (!factor_analyzed_) {
    factor_.analyze(hessian_);
    factor_analyzed_ = true;
  }
  const FactorizationResult f = factor_.factorize(hessian_);
  if (!f.success) throw EvaluationError("transient adjoint: a step Hessian is singular (" + f.message + ")");
  if (!low_rank_.empty()) factor_.set_low_rank_update(low_rank_.factors, low_rank_.core);
  have_factor_ = true;
  factor_step_ = step;
  ++statistics_.factorizations;
  statistics_.adjoint_factorization_seconds += seconds_since(t0);
  t0 = Clock::now();
  Vector v = factor_.solve(rhs);
  statistics_.adjoint_solve_seconds += seconds_since(t0);
  return v;
}

Vector TransientFunctional::solve_with_linear_solver(LinearSolver& solver, const Vector& rhs, int step) {
  // hessian_ holds the exact step Hessian; its low-rank parts (low_rank_) would be lost.
  if (!low_rank_.empty())
    throw EvaluationError("transient adjoint: the linear solver '" + solver.name() +
                          "' does not support terms with low-rank Hessian parts (step " +
                          std::to_string(step) + ")");
  std::string message;
  if (!solver.setup(hessian_, message))
    throw EvaluationError("transient adjoint: linear solver '" + solver.name() + "' set-up failed at step " +
                          std::to_string(step) + ": " + message);
  Vector v;
  const LinearSolveStats stats = solver.solve(rhs, options_.linear_relative_tolerance, v);
  ++statistics_.linear_solver_solves;
  statistics_.linear_solver_iterations += stats.iterations;
  statistics_.last_linear_solve = stats;
  if (!stats.converged)
    throw EvaluationError("transient adjoint: linear solver '" + solver.name() +
                          "' did not converge at step " + std::to_string(step) + ": " + stats.message);
  return v;
}

Vector TransientFunctional::solve_step_hessian(const DynamicState& to, const Vector& rhs, bool release_stored) {
  // The exact Hessian of the step that produced `to`, at to.y (the terms configured for the
  // step); rhs and the result in full DOF space, the constrained entries of the result zero.
  const Model& model = integrator_.model();
  const Elimination& elim = model.elimination();
  Vector lambda;
  NewtonSolver& newton = integrator_.newton();
  auto assemble_hessian = [&] {
    const auto t0 = Clock::now();
    if (!take_stored_hessian(to.step, release_stored)) {
      newton.assembler().evaluate(to.y, p_, nullptr, nullptr, &hessian_, HessianMode::exact);
      ++statistics_.hessian_assemblies;
    }
    low_rank_ = newton.assembler().low_rank_hessian(to.y, p_);
    statistics_.adjoint_assembly_seconds += seconds_since(t0);
  };
  if (LinearSolver* solver = newton.options().linear_solver.get()) {
    assemble_hessian();
    const auto t0 = Clock::now();
    lambda = elim.expand_direction(solve_with_linear_solver(*solver, elim.reduce(rhs), to.step));
    statistics_.adjoint_solve_seconds += seconds_since(t0);
  } else if (model.hessian_is_constant()) {
    // Every step has the same Hessian (at these parameters): Newton's kept factor solves it.
    auto t0 = Clock::now();
    const FactorizationResult f = newton.factorize_hessian(p_, to.y, HessianMode::exact);
    if (!f.success)
      throw EvaluationError("transient adjoint: the step Hessian is singular (" + f.message + ")");
    if (f.kept) {
      ++statistics_.kept_factor_solves;
    } else {
      ++statistics_.factorizations;
      ++statistics_.hessian_assemblies;
    }
    statistics_.adjoint_factorization_seconds += seconds_since(t0);
    t0 = Clock::now();
    lambda = elim.expand_direction(newton.factorization().solve(elim.reduce(rhs)));
    statistics_.adjoint_solve_seconds += seconds_since(t0);
  } else {
    assemble_hessian();
    lambda = elim.expand_direction(solve_step(elim.reduce(rhs), to.step));
  }
  return lambda;
}

void TransientFunctional::backward_step(const DynamicState& from, const DynamicState& to, Adjoint& a,
                                        Vector& gradient_p) {
  // Step from -> to solved S^T dPi/dx = 0 with
  //   dPi/dx = c M (x - x~) - g + dE/dx + dD/dv((x - x^)/kappa)
  // and produced v = (x - x^)/kappa and (Newmark) f = c M (x - x~) - g. `a` holds the
  // adjoints of `to`; on return, those of `from` (objective terms not included).
  integrator_.configure_step(from, p_);
  const StepMap m = integrator_.step_map(from);
  const Model& model = integrator_.model();
  InertiaTerm& inertia = integrator_.inertia();
  const MassOperator& mass = inertia.mass();
  const double c = m.inertia, kappa = m.velocity_scale;
  const Eigen::Index n = to.x.size();

  Vector x_total = a.x + a.v / kappa;  // total adjoint of x_{n+1}
  Vector predictor_bar = Vector::Zero(n), base_bar = -a.v / kappa, force_bar;
  if (m.carries_force) {
    mass.add_times(p_, a.force, x_total, c);
    mass.add_times(p_, a.force, predictor_bar, -c);
    force_bar = -a.force;  // and c fb^T M_e (x - x~) into gradient_p with the products below
  }
  const Vector lambda = solve_step_hessian(to, x_total, true);
  const auto t0 = Clock::now();
  mass.add_times(p_, lambda, predictor_bar, c);
  Vector start_x_bar = Vector::Zero(n), start_v_bar = Vector::Zero(n);  // through lagged damping coefficients
  if (DampingTerm* damping = integrator_.damping()) {
    damping->add_hessian_times(to.x, p_, lambda, base_bar);
    damping->add_step_start_transpose_times(to.x, p_, lambda, start_x_bar, start_v_bar);
  }
  if (m.carries_force) force_bar += lambda;
  // (d2 Pi/dx dp)^T lambda term by term; Newmark's inertia term also carries -fb (above), so
  // its product takes lambda - fb in one pass over the mass's elements instead of two.
  Vector products = Vector::Zero(p_.size());
  Vector inertia_weight;
  if (m.carries_force) inertia_weight = lambda - a.force;
  for (const auto& term : model.terms())
    term->add_mixed_transpose_times(
        to.x, p_, term.get() == &inertia && m.carries_force ? inertia_weight : lambda, products);
  gradient_p -= products;
  statistics_.adjoint_products_seconds += seconds_since(t0);

  Adjoint previous(n);
  previous.x = a.x_previous + m.predictor_x * predictor_bar + m.base_x * base_bar - start_x_bar;
  previous.v = a.v_previous + m.predictor_v * predictor_bar + m.base_v * base_bar - start_v_bar;
  if (m.predictor_x_previous != 0.0 || m.base_x_previous != 0.0)
    previous.x_previous = m.predictor_x_previous * predictor_bar + m.base_x_previous * base_bar;
  if (m.predictor_v_previous != 0.0) previous.v_previous = m.predictor_v_previous * predictor_bar;
  if (m.carries_force) previous.force = force_bar;
  a = std::move(previous);
}

Vector TransientFunctional::objective_gradient(const Vector& z, TrajectoryObjectivePtr other) {
  if (!other) throw std::invalid_argument("TransientFunctional::objective_gradient: no objective");
  // The forward pass first, with the own objective, so that its value stays the functional's;
  // the backward pass then reads the other objective's gradients along the kept trajectory.
  forward(z);
  struct Swap {
    TrajectoryObjectivePtr& slot;
    TrajectoryObjectivePtr kept;
    ~Swap() { slot = std::move(kept); }
  } swap{objective_, objective_};
  objective_ = std::move(other);
  Vector gradient;
  value_and_gradient(z, gradient);
  return gradient;
}

double TransientFunctional::value_and_gradient(const Vector& z, Vector& gradient) {
  forward(z);
  const auto t0 = Clock::now();
  const Eigen::Index n = x_init_.size();
  const int N = options_.steps, k = options_.checkpoint_interval;
  Vector gradient_p = Vector::Zero(p_.size());
  Adjoint a(n);
  have_factor_ = false;
  factor_step_ = -1;
  statistics_.factorizations = statistics_.cg_solves = statistics_.cg_iterations = 0;
  statistics_.kept_factor_solves = 0;
  statistics_.linear_solver_solves = 0;
  statistics_.linear_solver_iterations = 0;
  statistics_.last_linear_solve = {};
  statistics_.recomputed_steps = 0;
  statistics_.hessian_assemblies = statistics_.stored_hessians_used = 0;
  statistics_.adjoint_assembly_seconds = statistics_.adjoint_factorization_seconds = 0.0;
  statistics_.adjoint_solve_seconds = statistics_.adjoint_products_seconds = 0.0;
  statistics_.adjoint_recompute_seconds = statistics_.max_preconditioner_residual = 0.0;
  statistics_.adjoint_start_seconds = 0.0;
  const SparseCholesky& newton_factor = integrator_.newton().factorization();
  const long factorizations0 = newton_factor.numeric_factorizations() + factor_.numeric_factorizations();
  const long solves0 = newton_factor.back_solves() + factor_.back_solves();

  // Walk back through consecutive pairs of states; `states` holds one segment.
  auto backward_over = [&](const std::vector<const DynamicState*>& states) {
    for (std::size_t i = states.size() - 1; i > 0; --i) {
      backward_step(*states[i - 1], *states[i], a, gradient_p);
      add_objective_gradient(*states[i - 1], a, gradient_p);
    }
  };
  if (k <= 1) {
    add_objective_gradient(stored_.back(), a, gradient_p);
    std::vector<const DynamicState*> all;
    for (const DynamicState& s : stored_) all.push_back(&s);
    backward_over(all);
  } else {
    add_objective_gradient(tail_.back(), a, gradient_p);
    std::vector<DynamicState> recomputed;
    for (int j = static_cast<int>(stored_.size()) - 1; j >= 0; --j) {
      std::vector<const DynamicState*> seg{&stored_[j]};
      if (j == static_cast<int>(stored_.size()) - 1) {
        for (const DynamicState& s : tail_) seg.push_back(&s);
      } else {
        recomputed.assign(1, stored_[j]);
        recomputed.reserve(k + 1);
        const int end = std::min((j + 1) * k, N);
        const auto t_recompute = Clock::now();
        for (int step = j * k; step < end; ++step) {
          DynamicState s = recomputed.back();
          const NewtonResult r = integrator_.step(s, p_);
          if (!r.converged())
            throw EvaluationError("recomputation of step " + std::to_string(step + 1) + " failed");
          if (r.factorizations() > 0) newton_factor_step_ = s.step;
          keep_step_hessian(s.step);
          recomputed.push_back(std::move(s));
          ++statistics_.recomputed_steps;
          ++statistics_.forward_steps;
        }
        statistics_.adjoint_recompute_seconds += seconds_since(t_recompute);
        for (std::size_t i = 1; i < recomputed.size(); ++i) seg.push_back(&recomputed[i]);
        const int count = static_cast<int>(stored_.size() + recomputed.size());
        if (count > statistics_.stored_states_peak) {
          statistics_.stored_states_peak = count;
          statistics_.stored_megabytes_peak = count * state_megabytes(stored_[j]);
        }
      }
      backward_over(seg);
    }
  }

  // Newmark's memory starts at g_0 = -dPi_0/dx(x_0), Pi_0 = E + h D((x - x_0 + h v_0)/h).
  if (integrator_.options().scheme == TimeScheme::newmark) {
    const auto t_start = Clock::now();
    integrator_.configure_initial_force(x_init_, v_init_);
    const Model& model = integrator_.model();
    Vector damping_times = Vector::Zero(n);
    Vector start_x_bar = Vector::Zero(n), start_v_bar = Vector::Zero(n);
    if (DampingTerm* damping = integrator_.damping()) {
      damping->add_hessian_times(x_init_, p_, a.force, damping_times);
      damping->add_step_start_transpose_times(x_init_, p_, a.force, start_x_bar, start_v_bar);
    }
    a.x -= start_x_bar;
    a.v -= start_v_bar;
    a.x += damping_times;
    // a.x is read only as the gradient in designed initial positions: the Hessian product
    // (EnergyTerm's default builds each term's pattern and element Hessians, about a forward
    // step's cost on a large mesh) only then.
    if (options_.design_initial_positions) a.x -= model.hessian_times(x_init_, p_, a.force);
    a.v -= integrator_.options().time_step * damping_times;
    gradient_p -= model.mixed_transpose_times(x_init_, p_, a.force);
    statistics_.adjoint_start_seconds = seconds_since(t_start);
  }

  Vector extended(num_extended_params());
  extended.head(p_.size()) = gradient_p;
  Eigen::Index offset = p_.size();
  if (options_.design_initial_positions) extended.segment(offset, n) = a.x, offset += n;
  if (options_.design_initial_velocities) extended.segment(offset, n) = a.v;
  gradient = parameterization_->jacobian_transpose_times(z, extended);
  statistics_.adjoint_numeric_factorizations =
      newton_factor.numeric_factorizations() + factor_.numeric_factorizations() - factorizations0;
  statistics_.adjoint_back_solves = newton_factor.back_solves() + factor_.back_solves() - solves0;
  statistics_.adjoint_seconds = seconds_since(t0);
  counters_.adjoint_solves += N;
  counters_.adjoint_seconds += statistics_.adjoint_seconds;
  return value_;
}

}  // namespace tailor
