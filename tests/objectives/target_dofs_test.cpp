// TargetDofs: derivative checks (the checks' own ability to fail is shown in
// failing_check_test.cpp), the value by hand, and bad input.
#include "objectives/target_dofs.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "objective_checks.hpp"

namespace tailor::target_dofs_test {
namespace {

using testing::random_vector;

// A state that is not positions only: 5 vertices x 3 coordinates, then 4 extra entries (a rod's
// twists); targets on some coordinates of some vertices and on one extra entry.
struct DofState {
  Vector x = random_vector(19, 3);
  Vector p = random_vector(2, 4);
  std::vector<int> dofs{1, 3, 4, 11, 17};
  Vector targets = random_vector(5, 5, 0.5);
  double weight = 2.5;
};

TEST(TargetDofs, DerivativesMatchDifferences) {
  const DofState s;
  const TargetDofs J(s.dofs, s.targets, s.weight);
  const Vector dx = random_vector(s.x.size(), 6);
  const Vector none = Vector::Zero(s.p.size());
  TAILOR_EXPECT_CHECK(testing::check_gradient_x(J, s.x, s.p, dx));
  TAILOR_EXPECT_CHECK(testing::check_hessian(J, s.x, s.p, dx, none));
  TAILOR_EXPECT_CHECK(testing::check_residual_jacobians(J, s.x, s.p, dx, none));
  testing::expect_least_squares_consistent(J, s.x, s.p);
  EXPECT_EQ(testing::gradient_p(J, s.x, s.p), Vector::Zero(s.p.size()));
}

TEST(TargetDofs, ValueByHandAndZeroAtTheTargets) {
  const DofState s;
  const TargetDofs J(s.dofs, s.targets, s.weight);
  double expected = 0.0;
  for (std::size_t i = 0; i < s.dofs.size(); ++i)
    expected += 0.5 * s.weight * std::pow(s.x[s.dofs[i]] - s.targets[static_cast<Eigen::Index>(i)], 2);
  EXPECT_NEAR(J.value(s.x, s.p), expected, 1e-14);
  EXPECT_EQ(J.num_residuals(), 5);
  Vector at_target = s.x;
  for (std::size_t i = 0; i < s.dofs.size(); ++i) at_target[s.dofs[i]] = s.targets[static_cast<Eigen::Index>(i)];
  EXPECT_EQ(J.value(at_target, s.p), 0.0);
  // Entries that are not selected do not count.
  at_target[0] += 1.0;
  EXPECT_EQ(J.value(at_target, s.p), 0.0);
}

TEST(TargetDofs, BadInputIsRefused) {
  const Vector t2 = Vector::Zero(2);
  EXPECT_THROW(TargetDofs({}, Vector()), std::invalid_argument);
  EXPECT_THROW(TargetDofs({0, 1}, Vector::Zero(3)), std::invalid_argument);
  EXPECT_THROW(TargetDofs({0, -1}, t2), std::invalid_argument);
  EXPECT_THROW(TargetDofs({2, 2}, t2), std::invalid_argument);
  EXPECT_THROW(TargetDofs({0, 1}, Vector::Constant(2, std::nan(""))), std::invalid_argument);
  EXPECT_THROW(TargetDofs({0, 1}, t2, -1.0), std::invalid_argument);
  const TargetDofs J({0, 7}, t2);
  EXPECT_THROW(J.value(Vector::Zero(5), Vector()), std::invalid_argument);  // DOF 7 not in the state
}

}  // namespace
}  // namespace tailor::target_dofs_test
