#pragma once
// A reduced elastic model in the displacement coordinates q whose material depends linearly on
// design coordinates w: with moduli E = E0 (1 + sum_j w_j y_j) and an energy density linear in
// Young's modulus at fixed Poisson's ratio,
//
//   W(q; w) = W_0(q) + sum_j w_j W_j(q),
//
// so the reduced force dW/dq is affine in w and the mixed derivative d(force)/dw_j = dW_j/dq
// depends on q alone. The reduced design loop (adjoint/reduced_equilibrium_functional.hpp)
// needs W, its q-derivatives (Newton in q) and lambda^T d(force)/dw (the adjoint gradient).
// Implementations: PolynomialDesignModel (StVK and linear materials, exact precomputed
// polynomial coefficients) and CubatureDesignModel (any material, a cubature rule).
#include <functional>
#include <string>

#include "forward/core/types.hpp"

namespace tailor {

class ReducedDesignModel {
 public:
  virtual ~ReducedDesignModel() = default;
  virtual std::string name() const = 0;
  virtual int size() const = 0;         // r, displacement coordinates
  virtual int design_size() const = 0;  // m, design coordinates
  // W, dW/dq and d2W/dq2 at (q, w); null pointers: not wanted. Where the model cannot be
  // evaluated (an inverted element of a barrier material) the energy is +inf and the force and
  // stiffness are NaN, which Newton's line search rejects.
  virtual void evaluate(const Vector& q, const Vector& w, double* energy, Vector* force,
                        Matrix* stiffness) const = 0;
  // The model at a fixed design, for the many evaluations of one Newton solve: W, dW/dq,
  // d2W/dq2 at q. By default evaluate(q, w, ...); a model may precompute what depends on w.
  using AtDesign = std::function<void(const Vector& q, double* energy, Vector* force, Matrix* stiffness)>;
  virtual AtDesign at_design(const Vector& w) const {
    return [this, w](const Vector& q, double* energy, Vector* force, Matrix* stiffness) {
      evaluate(q, w, energy, force, stiffness);
    };
  }
  // d(dW/dq)/dw, r x m.
  virtual Matrix force_design_derivative(const Vector& q) const = 0;
  // lambda^T d(dW/dq)/dw (m), the adjoint's mixed term; by default from the matrix.
  virtual Vector force_design_derivative_transpose(const Vector& q, const Vector& lambda) const {
    return force_design_derivative(q).transpose() * lambda;
  }
};

}  // namespace tailor
