#pragma once
// Small analytic ReducedFunctionals with known minimizers, for the optimizer tests.
#include <functional>

#include "optimizers/optimizer.hpp"

namespace tailor::test {

// Base with a hook called before every evaluation (value, gradient, residuals, Hessian-vector
// product) with the 1-based call number: tests use it to throw EvaluationError, raise SIGINT
// or slow the functional down. Counts one forward solve per evaluation and one adjoint solve
// per gradient, like a simulation-backed functional would.
class HookedFunctional : public ReducedFunctional {
 public:
  std::function<void(const Vector& z, int call)> hook;
  int calls = 0;

 protected:
  void before(const Vector& z, bool gradient) {
    ++calls;
    if (hook) hook(z, calls);
    ++counters_.evaluations;
    ++counters_.forward_solves;
    if (gradient) ++counters_.adjoint_solves;
  }
};

// Chained Rosenbrock in residual form: r = (10 (z_{i+1} - z_i^2), 1 - z_i), i = 0..n-2, and
// J = 1/2 ||r||^2 = sum 50 (z_{i+1} - z_i^2)^2 + 1/2 (1 - z_i)^2 (half the textbook
// function, same minimizer z = 1 with J = 0).
class Rosenbrock : public HookedFunctional {
 public:
  explicit Rosenbrock(int n, bool residual_form = true) : n_(n), residual_form_(residual_form) {}

  int size() const override { return n_; }
  double value(const Vector& z) override {
    before(z, false);
    return 0.5 * residual_vector(z).squaredNorm();
  }
  double value_and_gradient(const Vector& z, Vector& gradient) override {
    before(z, true);
    const Vector r = residual_vector(z);
    gradient = jacobian(z).transpose() * r;
    return 0.5 * r.squaredNorm();
  }
  bool has_hessian_vector() const override { return true; }
  // J^T J v plus the residuals' curvature: only r_{2i} = 10 (z_{i+1} - z_i^2) has any,
  // d2 r_{2i} / dz_i^2 = -20.
  Vector hessian_vector(const Vector& z, const Vector& v) override {
    before(z, true);
    const Matrix J = jacobian(z);
    const Vector r = residual_vector(z);
    Vector result = J.transpose() * (J * v);
    for (int i = 0; i + 1 < n_; ++i) result[i] += -20.0 * r[2 * i] * v[i];
    return result;
  }
  bool has_residuals() const override { return residual_form_; }
  int num_residuals() const override { return residual_form_ ? 2 * (n_ - 1) : 0; }
  void residuals(const Vector& z, Vector& r, Matrix* J) override {
    if (!residual_form_) ReducedFunctional::residuals(z, r, J);  // throws
    before(z, J != nullptr);
    r = residual_vector(z);
    if (J) *J = jacobian(z);
  }

 private:
  Vector residual_vector(const Vector& z) const {
    Vector r(2 * (n_ - 1));
    for (int i = 0; i + 1 < n_; ++i) {
      r[2 * i] = 10.0 * (z[i + 1] - z[i] * z[i]);
      r[2 * i + 1] = 1.0 - z[i];
    }
    return r;
  }
  Matrix jacobian(const Vector& z) const {
    Matrix J = Matrix::Zero(2 * (n_ - 1), n_);
    for (int i = 0; i + 1 < n_; ++i) {
      J(2 * i, i) = -20.0 * z[i];
      J(2 * i, i + 1) = 10.0;
      J(2 * i + 1, i) = -1.0;
    }
    return J;
  }

  int n_;
  bool residual_form_;
};

// J = 1/2 sum w_i (z_i - p_i)^2 in R^3, w = (1, 2, 3), p = (1, 2, 3).
class WeightedQuadratic : public HookedFunctional {
 public:
  static Vector weights() { return Vector::LinSpaced(3, 1.0, 3.0); }
  static Vector center() { return Vector::LinSpaced(3, 1.0, 3.0); }

  int size() const override { return 3; }
  double value(const Vector& z) override {
    before(z, false);
    return 0.5 * (weights().array() * (z - center()).array().square()).sum();
  }
  double value_and_gradient(const Vector& z, Vector& gradient) override {
    before(z, true);
    gradient = weights().cwiseProduct(z - center());
    return 0.5 * (weights().array() * (z - center()).array().square()).sum();
  }
  bool has_hessian_vector() const override { return true; }
  Vector hessian_vector(const Vector& z, const Vector& v) override {
    before(z, true);
    return weights().cwiseProduct(v);
  }
};

// Linear constraints for WeightedQuadratic: a . z - b (= 0 or <= 0).
inline Constraint linear_constraint(const std::string& name, bool equality, const Vector& a, double b) {
  return {name, equality, [a, b](const Vector& z, Vector* gradient) {
            if (gradient) *gradient = a;
            return a.dot(z) - b;
          }};
}
// z0 + z1 + z2 = 3
inline Constraint sum_constraint() {
  Vector a(3);
  a << 1.0, 1.0, 1.0;
  return linear_constraint("sum", true, a, 3.0);
}
// z2 - z0 <= 1
inline Constraint gap_constraint() {
  Vector a(3);
  a << -1.0, 0.0, 1.0;
  return linear_constraint("gap", false, a, 1.0);
}

}  // namespace tailor::test
