#pragma once
// A reduced elastic potential: the energy of displacements in a basis, u = Phi q,
//   W(q) = E(x_rest + Phi q),
// with its gradient, the reduced internal force Phi^T f_int (f_int = dE/dx, the force the body
// exerts against the deformation), and its Hessian, the reduced tangent stiffness Phi^T K Phi.
// Implementations: ReducedStvk (exact cubic polynomial, cost independent of the mesh) and
// ProjectedReducedModel (any material, cost proportional to the mesh).
#include "forward/core/types.hpp"

namespace tailor {

class ReducedElasticModel {
 public:
  virtual ~ReducedElasticModel() = default;
  virtual int size() const = 0;  // r, the number of reduced coordinates
  // Any of W [energy], dW/dq [force] and d2W/dq2 [force / length] at q; null pointers are not
  // requested. force and stiffness are resized.
  virtual void evaluate(const Vector& q, double* energy, Vector* force, Matrix* stiffness) const = 0;

  double energy(const Vector& q) const {
    double e = 0.0;
    evaluate(q, &e, nullptr, nullptr);
    return e;
  }
  Vector force(const Vector& q) const {
    Vector f;
    evaluate(q, nullptr, &f, nullptr);
    return f;
  }
  Matrix stiffness(const Vector& q) const {
    Matrix k;
    evaluate(q, nullptr, nullptr, &k);
    return k;
  }
};

}  // namespace tailor
