#include "adjoint/reduced_functional.hpp"

namespace tailor {

Vector ReducedFunctional::hessian_vector(const Vector& z, const Vector& v) {
  (void)z, (void)v;
  throw std::logic_error("this functional offers no Hessian-vector products");
}

Vector ReducedFunctional::gauss_newton_vector(const Vector& z, const Vector& v) {
  (void)z, (void)v;
  throw std::logic_error("this functional offers no Gauss-Newton products");
}

void ReducedFunctional::residuals(const Vector& z, Vector& r, Matrix* jacobian) {
  (void)z, (void)r, (void)jacobian;
  throw std::logic_error("this functional has no residual form");
}

}  // namespace tailor
