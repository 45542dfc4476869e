// Objective's second derivatives are opt-in (objectives/objective.hpp): a term that does not
// provide add_hessian_times must not contribute a silent zero to Hessian-vector products, whether
// it forgot both overrides or claimed second derivatives without the product.
#include "objectives/objective.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>

#include "objectives/tikhonov.hpp"
#include "objectives/weighted_sum.hpp"

namespace tailor::objective_contract_test {
namespace {

// J = 1/2 |x|^2 + 1/2 |p|^2 with its gradients and nothing else: the term a user writes first.
class FirstOrderOnly : public Objective {
 public:
  std::string name() const override { return "first_order_only"; }
  double value(const Vector& x, const Vector& p) const override {
    return 0.5 * x.squaredNorm() + 0.5 * p.squaredNorm();
  }
  void add_gradient_x(const Vector& x, const Vector&, Vector& gx) const override { gx += x; }
  void add_gradient_p(const Vector&, const Vector& p, Vector& gp) const override { gp += p; }
};

// The same term, claiming second derivatives but forgetting the product.
class ClaimsWithoutProduct final : public FirstOrderOnly {
 public:
  std::string name() const override { return "claims_without_product"; }
  bool has_second_derivatives() const override { return true; }
};

TEST(ObjectiveContract, ATermWithoutSecondDerivativesSaysSo) {
  const FirstOrderOnly J;
  EXPECT_FALSE(J.has_second_derivatives());
  Vector out_x = Vector::Zero(3), out_p = Vector::Zero(2);
  try {
    J.add_hessian_times(Vector::Ones(3), Vector::Ones(2), Vector::Ones(3), Vector::Ones(2), out_x, out_p);
    FAIL() << "add_hessian_times of a term without it returned";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("first_order_only"), std::string::npos) << e.what();
  }
  EXPECT_EQ(out_x.norm() + out_p.norm(), 0.0);
}

TEST(ObjectiveContract, AClaimWithoutTheProductThrowsInsteadOfAddingZero) {
  const ClaimsWithoutProduct J;
  ASSERT_TRUE(J.has_second_derivatives());
  Vector out_x = Vector::Zero(3), out_p = Vector::Zero(2);
  EXPECT_THROW(J.add_hessian_times(Vector::Ones(3), Vector::Ones(2), Vector::Ones(3), Vector::Ones(2), out_x, out_p),
               std::logic_error);
}

// In a sum, one first-order term takes the sum's second derivatives away; a sum of terms that
// provide them keeps them (Tikhonov on p[0, 2): J_pp = alpha I there).
TEST(ObjectiveContract, ASumHasSecondDerivativesOnlyIfEveryPartHas) {
  const auto tikhonov = std::make_shared<Tikhonov>(0, 2, 3.0, Vector::Zero(2));
  const WeightedSum with_first_order({tikhonov, std::make_shared<FirstOrderOnly>()}, {1.0, 1.0});
  EXPECT_FALSE(with_first_order.has_second_derivatives());
  Vector out_x = Vector::Zero(3), out_p = Vector::Zero(2);
  EXPECT_THROW(with_first_order.add_hessian_times(Vector::Ones(3), Vector::Ones(2), Vector::Ones(3),
                                                  Vector::Ones(2), out_x, out_p),
               std::logic_error);

  const WeightedSum second_order({tikhonov}, {2.0});
  ASSERT_TRUE(second_order.has_second_derivatives());
  out_p.setZero();
  second_order.add_hessian_times(Vector::Ones(3), Vector::Ones(2), Vector::Zero(3), Vector::Ones(2), out_x, out_p);
  EXPECT_GT(out_p.norm(), 0.0) << "a term that provides second derivatives contributes them";
}

}  // namespace
}  // namespace tailor::objective_contract_test
