#pragma once
// ReducedFunctional: a scalar function of the design variables z whose evaluation may hide a
// forward solve (x*(p(z))) and an adjoint solve. This is what every optimizer back-end takes.
//
// Contract: value_and_gradient(z, g) returns J(z) and fills g = dJ/dz (size size()). Calls
// with the same z may be served from a cache. Hessian-vector products and the residual form
// (J = 1/2 ||r(z)||^2, for Gauss-Newton / least-squares back-ends) are optional.
#include <stdexcept>
#include <string>

#include "forward/core/types.hpp"

namespace tailor {

// Work counters, reported by optimizers.
struct FunctionalCounters {
  int evaluations = 0;      // value or value_and_gradient calls that were not cached
  int forward_solves = 0;   // Newton solves
  int adjoint_solves = 0;   // linear solves with the Hessian transpose
  double forward_seconds = 0.0;
  double adjoint_seconds = 0.0;
  // Where a functional counts them (StaticFunctional does; 0 otherwise): numeric factorizations
  // of the state Hessian, back-solves with a factor (also as a CG preconditioner), and
  // Hessian-vector or Gauss-Newton products.
  long factorizations = 0;
  long back_solves = 0;
  int hessian_vectors = 0;
};

class ReducedFunctional {
 public:
  virtual ~ReducedFunctional() = default;
  virtual int size() const = 0;  // number of design variables
  virtual double value(const Vector& z) = 0;
  virtual double value_and_gradient(const Vector& z, Vector& gradient) = 0;

  // Hessian-vector product d2J/dz2 v at z (optional).
  virtual bool has_hessian_vector() const { return false; }
  virtual Vector hessian_vector(const Vector& z, const Vector& v);
  // Gauss-Newton product (dr/dz)^T (dr/dz) v of the residual form at z (optional): the Hessian
  // without the residuals' curvature, positive semidefinite, without forming dr/dz.
  virtual bool has_gauss_newton_vector() const { return false; }
  virtual Vector gauss_newton_vector(const Vector& z, const Vector& v);
  // A positive estimate of the diagonal of the Gauss-Newton matrix at z, cheap next to a product
  // (no solves), for preconditioning CG on curvature products (optional: false without one).
  virtual bool gauss_newton_diagonal(const Vector& z, Vector& diagonal) {
    (void)z, (void)diagonal;
    return false;
  }

  // Residual form J = 1/2 ||r||^2 (optional): residuals and their Jacobian dr/dz.
  virtual bool has_residuals() const { return false; }
  virtual int num_residuals() const { return 0; }
  virtual void residuals(const Vector& z, Vector& r, Matrix* jacobian);

  // Raised when the functional cannot be evaluated at z (e.g. the forward solve failed);
  // optimizers treat it as an infinitely bad point and shorten their step.
  virtual const FunctionalCounters& counters() const { return counters_; }

 protected:
  FunctionalCounters counters_;
};

// Thrown by a functional whose forward solve failed at the requested z.
class EvaluationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace tailor
