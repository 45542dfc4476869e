// Adaptive barrier stiffness (Li et al. 2020, section 4.3): the least-squares balance of the
// barrier's gradient against the other forces, its clamping, the raise rule, and the kappa that
// makes one pair carry a force (checked against the barrier's own derivative).
#include "forward/contact/barrier_stiffness.hpp"

#include <gtest/gtest.h>

namespace tailor::contact::barrier_stiffness_test {
namespace {

TEST(BarrierStiffness, BalanceIsTheLeastSquaresKappa) {
  Vector barrier(4), other(4);
  barrier << 1.0, -2.0, 0.5, 0.0;
  other << -3.0, 6.0, -1.5, 0.0;  // exactly -3 x barrier
  EXPECT_NEAR(balanced_stiffness(other, barrier, 0.0, 1e9), 3.0, 1e-12);
  // The least squares kappa minimizes |other + k barrier|: perturb it and the residual grows.
  other[3] = 1.0;
  other[0] += 0.3;
  const double k = balanced_stiffness(other, barrier, 0.0, 1e9);
  for (double dk : {-1e-3, 1e-3})
    EXPECT_GT((other + (k + dk) * barrier).norm(), (other + k * barrier).norm());
  // Clamped to [lo, hi]; lo without active pairs or for a barrier pushing the same way.
  EXPECT_EQ(balanced_stiffness(other, barrier, 5.0, 1e9), 5.0);
  EXPECT_EQ(balanced_stiffness(other, barrier, 0.0, 2.0), 2.0);
  EXPECT_EQ(balanced_stiffness(other, Vector::Zero(4), 7.0, 1e9), 7.0);
  EXPECT_EQ(balanced_stiffness(barrier, barrier, 7.0, 1e9), 7.0);
}

TEST(BarrierStiffness, RaisedOnlyWhileTheDistanceShrinksBelowTheThreshold) {
  EXPECT_EQ(raised_stiffness(10.0, 2e-5, 1e-5, 5e-5, 2.0, 1e3), 20.0);  // below and shrinking
  EXPECT_EQ(raised_stiffness(10.0, 1e-5, 2e-5, 5e-5, 2.0, 1e3), 10.0);  // below but growing
  EXPECT_EQ(raised_stiffness(10.0, 2e-4, 1e-4, 5e-5, 2.0, 1e3), 10.0);  // shrinking above
  EXPECT_EQ(raised_stiffness(800.0, 2e-5, 1e-5, 5e-5, 2.0, 1e3), 1e3);  // capped
}

TEST(BarrierStiffness, StiffnessForForceMakesOnePairCarryIt) {
  const double d_hat = 0.01, force = 123.0;
  const double kappa = stiffness_for_force(force, d_hat);
  // -d(kappa b(d^2))/dd at d = d_hat / 2 by central differences of the barrier.
  const double d = 0.5 * d_hat, h = 1e-7;
  const double pushed =
      -kappa *
      (barrier((d + h) * (d + h), d_hat * d_hat).value - barrier((d - h) * (d - h), d_hat * d_hat).value) /
      (2 * h);
  EXPECT_NEAR(pushed, force, 1e-6 * force);
}

}  // namespace
}  // namespace tailor::contact::barrier_stiffness_test
