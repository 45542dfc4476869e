#pragma once
// Objective: a design objective J(x, p) of the full state x (world positions, interleaved) and
// the model parameters p, with its partial derivatives. The adjoint layer supplies dx/dp.
//
// Second-order terms (for Hessian-vector products of the reduced functional) are opt-in: an
// objective that provides them overrides both has_second_derivatives() (true) and
// add_hessian_times(). One that overrides neither reports false, so the adjoint layer and the
// back-ends do not use Hessian-vector products with it; one that claims them without the product
// gets an exception, never a silent zero (tests/objectives/objective_contract_test.cpp).
// Least-squares objectives (J = 1/2 ||r(x, p)||^2) expose r and its partial Jacobians so
// Gauss-Newton back-ends can use them.
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "forward/core/types.hpp"

namespace tailor {

class Objective {
 public:
  virtual ~Objective() = default;
  virtual std::string name() const = 0;
  virtual double value(const Vector& x, const Vector& p) const = 0;
  virtual void add_gradient_x(const Vector& x, const Vector& p, Vector& gx) const = 0;  // += dJ/dx
  virtual void add_gradient_p(const Vector& x, const Vector& p, Vector& gp) const {      // += dJ/dp
    (void)x, (void)p, (void)gp;
  }

  virtual bool has_second_derivatives() const { return false; }
  // += J_xx dx + J_xp dp  and  += J_px dx + J_pp dp (directional derivatives of the gradients).
  // Throws std::logic_error unless overridden.
  virtual void add_hessian_times(const Vector& x, const Vector& p, const Vector& dx, const Vector& dp,
                                 Vector& out_x, Vector& out_p) const {
    (void)x, (void)p, (void)dx, (void)dp, (void)out_x, (void)out_p;
    throw std::logic_error("objective '" + name() + "' provides no second derivatives (add_hessian_times)");
  }

  virtual bool is_least_squares() const { return false; }
  virtual int num_residuals() const { return 0; }
  // r(x, p), dr/dx (num_residuals x |x|) and dr/dp (num_residuals x |p|); J = 1/2 ||r||^2.
  virtual void residuals(const Vector& x, const Vector& p, Vector& r, SparseMatrix* dr_dx,
                         SparseMatrix* dr_dp) const {
    (void)x, (void)p, (void)r, (void)dr_dx, (void)dr_dp;
  }
};

using ObjectivePtr = std::shared_ptr<const Objective>;

}  // namespace tailor
