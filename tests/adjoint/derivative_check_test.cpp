#include "adjoint/derivative_check.hpp"

#include <gtest/gtest.h>

#include "../support/quadratic_term.hpp"

namespace tailor::derivative_check_test {
namespace {

using testing::QuadraticTerm;

// Wraps a term and corrupts one of its derivatives: the check must catch each corruption.
class CorruptedTerm final : public EnergyTerm {
 public:
  enum class Defect { none, gradient_sign, hessian_scale, param_gradient_zero, mixed_scale };
  CorruptedTerm(const EnergyTerm& inner, Defect defect) : inner_(inner), defect_(defect) {}
  std::string name() const override { return "corrupted"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& r) const override {
    Vector g = Vector::Zero(x.size());
    EnergyRequest inner_request = r;
    if (r.gradient) inner_request.gradient = &g;
    inner_.evaluate(x, p, inner_request);
    if (r.gradient) {
      if (defect_ == Defect::gradient_sign) g[1] = -g[1];
      *r.gradient += g;
    }
    if (r.hessian_values && defect_ == Defect::hessian_scale) r.hessian_values[0] *= 1.001;
  }
  void hessian_pattern(HessianPattern& pattern) const override { inner_.hessian_pattern(pattern); }
  void add_param_gradient(const Vector& x, const Vector& p, Vector& gp) const override {
    if (defect_ != Defect::param_gradient_zero) inner_.add_param_gradient(x, p, gp);
  }
  void add_mixed(const Vector& x, const Vector& p, Triplets& m) const override {
    Triplets inner;
    inner_.add_mixed(x, p, inner);
    for (auto& t : inner)
      m.emplace_back(t.row(), t.col(), defect_ == Defect::mixed_scale && t.row() == 2 ? 1.01 * t.value() : t.value());
  }

 private:
  const EnergyTerm& inner_;
  Defect defect_;
};

struct Fixture {
  QuadraticTerm term{testing::random_spd(8, 2), Vector::LinSpaced(8, -1.0, 1.0)};
  Vector x = Vector::LinSpaced(8, 0.2, 0.9);
  Vector p = Vector::Constant(1, 0.7);
};

const DerivativeCheck& find(const EnergyTermCheck& c, const std::string& quantity) {
  for (const auto& d : c.checks)
    if (d.quantity == quantity) return d;
  throw std::runtime_error("no check named " + quantity);
}

TEST(DerivativeCheck, CorrectTermPassesWithSecondOrderConvergence) {
  Fixture f;
  const EnergyTermCheck c = check_energy_term(f.term, f.x, f.p);
  EXPECT_TRUE(c.passed()) << c.table();
  ASSERT_EQ(c.checks.size(), 5u);
  // The cubic term makes truncation errors visible: central differences converge as h^2.
  EXPECT_NEAR(find(c, "gradient").observed_order, 2.0, 0.2) << c.table();
}

TEST(DerivativeCheck, EveryCorruptionIsCaught) {
  Fixture f;
  using D = CorruptedTerm::Defect;
  for (auto [defect, quantity] : {std::pair{D::gradient_sign, "gradient"}, std::pair{D::hessian_scale, "hessian"},
                                  std::pair{D::param_gradient_zero, "param_gradient"}, std::pair{D::mixed_scale, "mixed"}}) {
    const CorruptedTerm bad(f.term, defect);
    const EnergyTermCheck c = check_energy_term(bad, f.x, f.p);
    EXPECT_FALSE(c.passed()) << quantity << "\n" << c.table();
    EXPECT_FALSE(find(c, quantity).passed) << quantity;
  }
  const CorruptedTerm good(f.term, D::none);
  EXPECT_TRUE(check_energy_term(good, f.x, f.p).passed());
}

TEST(DerivativeCheck, VanishingDerivativeIsNotAPass) {
  // A constant function has zero derivative and zero differences: reported, not passed.
  DerivativeCheckOptions options;
  const DerivativeCheck c = check_directional_derivative(
      "constant", [](double) { return Vector::Constant(1, 3.0); }, Vector::Zero(1), options);
  EXPECT_FALSE(c.passed);
  EXPECT_TRUE(c.vanishing) << c.message;
  // A missing derivative (analytic zero, true derivative nonzero) fails too.
  const DerivativeCheck missing = check_directional_derivative(
      "linear", [](double t) { return Vector::Constant(1, 2.0 * t); }, Vector::Zero(1), options);
  EXPECT_FALSE(missing.passed);
}

}  // namespace
}  // namespace tailor::derivative_check_test
