// Elementwise maps without parameters: p = z and p = exp(z).
#include <cmath>

#include "adjoint/parameterizations/checked_map.hpp"

namespace tailor {
namespace {

using detail::concat;

void require_nonnegative_size(const char* factory, int n) {
  if (n < 0) detail::invalid_parameterization(factory, concat("size must be non-negative, got ", n));
}

class IdentityMap final : public detail::CheckedMap {
 public:
  explicit IdentityMap(int n) : n_(n) {}
  std::string name() const override { return concat("identity(", n_, ")"); }
  int num_design() const override { return n_; }
  int num_params() const override { return n_; }

 protected:
  Vector do_apply(const Vector& z) const override { return z; }
  Vector do_jacobian_times(const Vector&, const Vector& dz) const override { return dz; }
  Vector do_jacobian_transpose_times(const Vector&, const Vector& w) const override { return w; }

 private:
  int n_;
};

// p_i = exp(z_i). The Jacobian is diagonal, diag(exp(z)), so both products are the same
// elementwise scaling, and the second-order term is diagonal too: w_i exp(z_i) dz_i.
class ExpMap final : public detail::CheckedMap {
 public:
  explicit ExpMap(int n) : n_(n) {}
  std::string name() const override { return concat("exp(", n_, ")"); }
  int num_design() const override { return n_; }
  int num_params() const override { return n_; }

 protected:
  Vector do_apply(const Vector& z) const override { return z.array().exp().matrix(); }
  Vector do_jacobian_times(const Vector& z, const Vector& dz) const override {
    return (z.array().exp() * dz.array()).matrix();
  }
  Vector do_jacobian_transpose_times(const Vector& z, const Vector& w) const override {
    return (z.array().exp() * w.array()).matrix();
  }
  Vector do_second_derivative_times(const Vector& z, const Vector& w, const Vector& dz) const override {
    return (w.array() * z.array().exp() * dz.array()).matrix();
  }

 private:
  int n_;
};

}  // namespace

ParameterizationPtr identity_map(int n) {
  require_nonnegative_size("identity_map", n);
  return std::make_shared<IdentityMap>(n);
}

ParameterizationPtr exp_map(int n) {
  require_nonnegative_size("exp_map", n);
  return std::make_shared<ExpMap>(n);
}

}  // namespace tailor
