#pragma once
// EnergyTerm: one differentiable potential E(x, p) with first and second derivatives in the
// state x and the parameters p. A Model is a sum of such terms (see model.hpp).
//
// Second derivatives in x are delivered against a fixed sparsity pattern: a term announces
// its (row, col) slots once (hessian_pattern) and then, on every evaluation, writes one value
// per slot in the same order. The Model maps slots to the assembled matrix once, so Newton
// never rebuilds a sparse matrix from triplets.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "forward/core/types.hpp"

namespace tailor {

// What to evaluate and where to put it. Null pointers are not requested.
struct EnergyRequest {
  double* value = nullptr;          // += E
  Vector* gradient = nullptr;       // += dE/dx, size = number of DOFs
  double* hessian_values = nullptr; // = d2E/dx2 at the slots of hessian_pattern() (overwritten)
  HessianMode hessian_mode = HessianMode::exact;
};

// A dense low-rank part of a term's Hessian, kept off the sparse pattern:
//   d2E/dx2 = (values on hessian_pattern()) + factors * core * factors^T,
// factors n x k with few columns, core k x k symmetric (may be indefinite). Terms whose
// Hessian has a global low-rank part (damping along example deformations) report it here:
// on the pattern it would fill every row of the sparse factorization. Newton and the adjoint
// apply it to the sparse factor by the Sherman-Morrison-Woodbury identity.
struct LowRankHessian {
  Matrix factors;  // n x k
  Matrix core;     // k x k
  bool empty() const { return factors.cols() == 0; }
  // Appends scale * F G F^T (block-diagonal core).
  void append(const Matrix& F, const Matrix& G, double scale = 1.0);
  // out += factors core factors^T w.
  void add_times(const Vector& w, Vector& out) const;
};

class EnergyTerm {
 public:
  virtual ~EnergyTerm() = default;

  // A short name for reports and derivative-check tables ("elastic", "gravity", ...).
  virtual std::string name() const = 0;

  // Evaluate any of value / gradient / Hessian values at (x, p) in one pass.
  virtual void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const = 0;

  // The Hessian slots written by evaluate(), in order. Both (i, j) and (j, i) appear for
  // off-diagonal couplings; duplicates are allowed (they are summed). Empty for terms that
  // are linear in x.
  virtual void hessian_pattern(HessianPattern& pattern) const { (void)pattern; }

  // += dE/dp (size of p). Default: the term does not depend on p.
  virtual void add_param_gradient(const Vector& x, const Vector& p, Vector& gradient_p) const {
    (void)x, (void)p, (void)gradient_p;
  }
  // Mixed second derivatives d2E/(dx dp) as triplets (row: DOF, col: parameter index).
  virtual void add_mixed(const Vector& x, const Vector& p, Triplets& mixed) const {
    (void)x, (void)p, (void)mixed;
  }

  // Appends the low-rank part of d2E/dx2 (see LowRankHessian). Default: none.
  virtual void add_low_rank_hessian(const Vector& x, const Vector& p, LowRankHessian& update,
                                    HessianMode mode = HessianMode::exact) const {
    (void)x, (void)p, (void)update, (void)mode;
  }

  // out += (d2E/dx2) w in full DOF space (the default evaluates the Hessian values on the
  // pattern and multiplies slot by slot, without assembling a matrix, then adds the low-rank
  // part).
  virtual void add_hessian_times(const Vector& x, const Vector& p, const Vector& w, Vector& out,
                                 HessianMode mode = HessianMode::exact) const;

  // gradient_p += (d2E/dxdp)^T w, for one adjoint vector w (size of x). The default goes
  // through add_mixed(); terms with many parameters override it to avoid the triplets.
  virtual void add_mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w, Vector& gradient_p) const;

  // Whether d2E/dx2 is independent of the state x (linear elasticity, inertia, loads). Newton
  // then factorizes once per parameter vector and keeps that factor across its iterations,
  // time steps and the adjoint (NewtonSolver). It may still depend on p and on the term's
  // settings; a term whose settings outside p enter its constant Hessian (a time step's
  // inertia coefficient) changes hessian_revision() whenever they change. Default: false.
  virtual bool hessian_is_constant() const { return false; }
  virtual std::uint64_t hessian_revision() const { return 0; }

  // Largest admissible fraction in (0, 1] of the step x -> x + dx (e.g. from continuous
  // collision detection or to keep elements from inverting). Default: no restriction.
  virtual double max_step(const Vector& x, const Vector& dx) const {
    (void)x, (void)dx;
    return 1.0;
  }

  // Distributed assembly (LinearSolver::assembles_by_parts): the same energy restricted to
  // the elements for which keep(dofs, count) is true (dofs: the element's DOFs in x). Returns
  // false when the term cannot be split (it is then assembled whole by one process); else
  // `share` is the restricted term, or null when no element is kept. Default: cannot split.
  virtual bool share_by_elements(const std::function<bool(const int* dofs, int count)>& keep,
                                 std::unique_ptr<EnergyTerm>& share) const {
    (void)keep, (void)share;
    return false;
  }

  // Convenience wrappers around evaluate().
  double value(const Vector& x, const Vector& p) const;
  void add_gradient(const Vector& x, const Vector& p, Vector& gradient) const;
  // The term's Hessian on its pattern assembled as a full (both triangles) sparse matrix of
  // size n x n; it excludes the low-rank part (add_low_rank_hessian).
  SparseMatrix hessian(const Vector& x, const Vector& p, HessianMode mode) const;
};

}  // namespace tailor
