#pragma once
// StaticFunctional: the reduced functional of a static inverse problem,
//   J(z) = T(x*(p), p),  p = phi(z),  x*(p) = argmin_x E(x, p)  (with x = x0 + S y),
// with its gradient by the adjoint method (docs/methods.md section 2):
//   H lambda = S^T dT/dx,   dJ/dp = dT/dp - (d2E/dxdp)^T (S lambda),   dJ/dz = phi'(z)^T dJ/dp,
// where H = S^T (d2E/dx2) S is the exact Hessian at x*. The residual form (for least-squares
// objectives) differentiates x* in direct mode: dy/dp = -H^-1 S^T (d2E/dxdp).
//
// Linear solves with H reuse Newton's work: the Hessian at x* is already assembled by the
// converged Newton iteration, and the factorization of the previous iterate's exact Hessian
// preconditions a conjugate-gradient solve that needs a few iterations; only if that fails
// (projected or shifted factorization, indefinite H, slow convergence) is H factorized afresh
// (LDL^T when indefinite).
#include <memory>
#include <optional>

#include "adjoint/parameterization.hpp"
#include "adjoint/reduced_functional.hpp"
#include "forward/solve/newton.hpp"
#include "objectives/objective.hpp"

namespace tailor {

struct StaticFunctionalOptions {
  NewtonOptions newton = [] {
    NewtonOptions o;
    o.relative_tolerance = 1e-11;  // gradients are only as accurate as the equilibrium
    return o;
  }();
  bool warm_start = true;            // start Newton from the previous equilibrium
  // Of the preconditioned CG solves, and of the adjoint solves with newton.linear_solver (e.g.
  // PETSc's KSP). The rule: the gradient's relative error is at most about cond(H) times the
  // adjoint's relative residual, and the forward state is held to newton.relative_tolerance
  // (1e-11), so the adjoint is solved 10x tighter than the equilibrium (1e-12): its error then
  // stays below the error the equilibrium itself puts into the gradient.
  double linear_relative_tolerance = 1e-12;
  int max_cg_iterations = 25;
};

// How the last linear solve with the Hessian was done.
enum class HessianSolve { reused_factorization, preconditioned_cg, fresh_factorization, external_solver };
std::string to_string(HessianSolve method);

class StaticFunctional final : public ReducedFunctional {
 public:
  // `model` must outlive the functional; `rest_y` is the start of the first Newton solve (and
  // of any retry after a failed warm start).
  StaticFunctional(const Model& model, ParameterizationPtr parameterization, ObjectivePtr objective,
                   Vector rest_y, StaticFunctionalOptions options = {});

  int size() const override { return parameterization_->num_design(); }
  // The forward solves' settings (e.g. a tighter tolerance for a gradient check; they apply
  // from the next new z on).
  NewtonOptions& newton_options() { return newton_.options(); }
  double value(const Vector& z) override;
  double value_and_gradient(const Vector& z, Vector& gradient) override;

  // Second-order adjoint (one tangent and one second-order adjoint solve with H). The third
  // derivatives of E it needs, contracted with the adjoint (d/de of (d2E/dx2) lambda and of
  // (d2E/dxdp)^T lambda along (dx, dp)), are central differences of the exact second
  // derivatives with a relative step of 1e-5 (truncation error ~1e-10 relative); everything
  // else is exact. Available when the objective has second derivatives.
  bool has_hessian_vector() const override { return objective_->has_second_derivatives(); }
  Vector hessian_vector(const Vector& z, const Vector& v) override;
  // Gauss-Newton product (dr/dz)^T (dr/dz) v for least-squares objectives: a tangent solve for
  // (dr/dz) v and an adjoint solve for the transpose, no third derivatives.
  // Products at one z share its adjoint solution, the mixed block and the residual Jacobians,
  // and solve with a factorization of the exact Hessian at the equilibrium (made once per z when
  // the kept factor is another's): two back-solves per product.
  bool has_gauss_newton_vector() const override { return objective_->is_least_squares(); }
  Vector gauss_newton_vector(const Vector& z, const Vector& v) override;
  // The diagonal of the Gauss-Newton matrix with H^-1 replaced by diag(H)^-1 in the tangent
  // (the sensitivity dx/dp = -S H^-1 S^T E_xp made local; Jacobi), which keeps the residual
  // Jacobians' terms that do not pass through the state (a regularizer's) exact. Taken to z as
  // sum_i (dp_i/dz_j)^2 d_i, which needs each p_i to depend on at most one z_j (elementwise
  // maps, embeddings, region scatter); false for other parameterizations (detected by two
  // probes that disagree), for objectives without residual form and where the forward solve
  // left no assembled Hessian. A crude estimate (low by a median factor of 25 on a small
  // recovery); used only by newton_cg's optional preconditioner.
  bool gauss_newton_diagonal(const Vector& z, Vector& diagonal) override;

  bool has_residuals() const override { return objective_->is_least_squares(); }
  int num_residuals() const override { return objective_->num_residuals(); }
  void residuals(const Vector& z, Vector& r, Matrix* jacobian) override;

  // Direct mode: dx*/dz, one column per design variable (for few design variables).
  Matrix state_sensitivity(const Vector& z);
  // Products with dx*/dz at z for any scalar L(x*) a caller computes from the state (what an
  // autodiff framework chains through): the vector-Jacobian product (dx*/dz)^T w, with w =
  // dL/dx (all DOFs), is one adjoint solve, H lambda = S^T w, as in the gradient; the
  // Jacobian-vector product (dx*/dz) dz is one tangent solve. Both solve at the equilibrium
  // of z, with the factorization the forward solve left when it is H's.
  Vector state_vjp(const Vector& z, const Vector& w);
  Vector state_jvp(const Vector& z, const Vector& dz);

  // The equilibrium of the last forward solve and its parameters.
  const Vector& state() const { return x_; }
  const Vector& parameters() const { return p_; }
  const NewtonResult& last_newton() const { return newton_result_; }
  HessianSolve last_hessian_solve() const { return last_solve_; }
  int last_cg_iterations() const { return last_cg_iterations_; }
  // The last adjoint solve with newton.linear_solver (iterations, residual, tolerance).
  const LinearSolveStats& last_linear_solve() const { return last_linear_solve_; }

 private:
  // The adjoint at the current equilibrium: dT/dx, S lambda, and dJ/dp (total).
  struct FirstOrder {
    Vector jx, lambda, gradient_p;
  };
  const FirstOrder& first_order();  // computed once per equilibrium
  // dJ/dp of an objective with partial gradients jx, jp at the equilibrium (one adjoint solve).
  // With `mixed` (d2E/dxdp at the equilibrium), its transpose product replaces the element loop.
  Vector adjoint_gradient_p(const Vector& jx, Vector jp, Vector* lambda = nullptr,
                            const SparseMatrix* mixed = nullptr);
  // What products at the current z share: the mixed block d2E/dxdp, and the residual Jacobians
  // (Gauss-Newton products only). Factorizes H at the equilibrium unless the kept factor is H's.
  struct ProductData {
    SparseMatrix mixed, dr_dx, dr_dp;
    bool residual_jacobians;  // no default initializer: clang 14 then cannot construct it in std::optional
  };
  const ProductData& product_data(bool residual_jacobians);
  void count_factor_work();  // counters_.factorizations and back_solves from the factor's counts
  // dx*/dp along dp (direct mode), given the mixed block d2E/dxdp at the equilibrium.
  Vector tangent(const Vector& dp, const SparseMatrix& mixed);
  void forward(const Vector& z);             // solves unless z is the cached point
  Vector solve_hessian(const Vector& rhs);   // H v = rhs at the current equilibrium

  NewtonResult solve_refusing(const Vector& p, Vector& y);  // Newton; a refused p is an EvaluationError

  const Model& model_;
  ParameterizationPtr parameterization_;
  ObjectivePtr objective_;
  StaticFunctionalOptions options_;
  NewtonSolver newton_;
  Vector rest_y_, y_, x_, p_, z_;
  bool have_state_ = false;
  double objective_value_ = 0.0;
  NewtonResult newton_result_;
  HessianSolve last_solve_ = HessianSolve::fresh_factorization;
  int last_cg_iterations_ = 0;
  // newton.linear_solver: set up with the exact Hessian at the current equilibrium.
  bool adjoint_solver_ready_ = false;
  SparseMatrix adjoint_hessian_;
  LinearSolveStats last_linear_solve_;
  // Valid for the current equilibrium (reset by each new forward solve).
  std::optional<FirstOrder> first_;
  std::optional<ProductData> products_;
};

}  // namespace tailor
