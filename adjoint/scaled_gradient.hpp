#pragma once
// A reduced functional whose gradient is the inner one's times a factor, with the same value.
// For the checks that show a Taylor test can fail: a gradient 1% off (a factor 1.01) must fail it.
#include "adjoint/reduced_functional.hpp"

namespace tailor {

class ScaledGradient final : public ReducedFunctional {
 public:
  ScaledGradient(ReducedFunctional& inner, double scale) : inner_(inner), scale_(scale) {}
  int size() const override { return inner_.size(); }
  double value(const Vector& z) override { return inner_.value(z); }
  double value_and_gradient(const Vector& z, Vector& gradient) override {
    const double value = inner_.value_and_gradient(z, gradient);
    gradient *= scale_;
    return value;
  }

 private:
  ReducedFunctional& inner_;
  double scale_;
};

}  // namespace tailor
