// LinearObservations: derivative checks (the checks' own ability to fail is shown in
// failing_check_test.cpp), the mean of a vertex set by hand, and bad input.
#include "objectives/linear_observations.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "objective_checks.hpp"

namespace tailor::linear_observations_test {
namespace {

using testing::random_vector;

// Two observations on a 6-vertex, 3D state: the mean x of vertices {1, 4, 5} and a mixed
// combination of three entries.
SparseMatrix observations() {
  std::vector<Eigen::Triplet<double>> t;
  for (int v : {1, 4, 5}) t.emplace_back(0, 3 * v, 1.0 / 3.0);
  t.emplace_back(1, 2, 0.5);
  t.emplace_back(1, 9, -1.5);
  t.emplace_back(1, 16, 2.0);
  SparseMatrix b(2, 18);
  b.setFromTriplets(t.begin(), t.end());
  return b;
}

TEST(LinearObservations, DerivativesMatchDifferences) {
  const Vector x = random_vector(18, 3), p = random_vector(2, 4), dx = random_vector(18, 6);
  const LinearObservations J(observations(), random_vector(2, 5), (Vector(2) << 2.5, 0.7).finished());
  const Vector none = Vector::Zero(p.size());
  TAILOR_EXPECT_CHECK(testing::check_gradient_x(J, x, p, dx));
  TAILOR_EXPECT_CHECK(testing::check_hessian(J, x, p, dx, none));
  TAILOR_EXPECT_CHECK(testing::check_residual_jacobians(J, x, p, dx, none));
  testing::expect_least_squares_consistent(J, x, p);
  EXPECT_EQ(testing::gradient_p(J, x, p), Vector::Zero(p.size()));
}

TEST(LinearObservations, TheMeanOfAVertexSetByHand) {
  const Vector x = random_vector(18, 7);
  const Vector targets = (Vector(2) << 0.3, -0.2).finished(), weights = (Vector(2) << 4.0, 0.0).finished();
  const LinearObservations J(observations(), targets, weights);
  const double mean = (x[3] + x[12] + x[15]) / 3.0;
  EXPECT_NEAR(J.value(x, Vector()), 0.5 * 4.0 * std::pow(mean - 0.3, 2), 1e-14);
  EXPECT_NEAR(J.misfit(x)[1], 0.5 * x[2] - 1.5 * x[9] + 2.0 * x[16] + 0.2, 1e-14);
}

TEST(LinearObservations, BadInputIsRefused) {
  const Vector two = Vector::Ones(2);
  EXPECT_THROW(LinearObservations(SparseMatrix(0, 4), Vector(), Vector()), std::invalid_argument);
  EXPECT_THROW(LinearObservations(observations(), Vector::Ones(3), two), std::invalid_argument);
  EXPECT_THROW(LinearObservations(observations(), two, Vector::Ones(1)), std::invalid_argument);
  EXPECT_THROW(LinearObservations(observations(), two, -two), std::invalid_argument);
  EXPECT_THROW(LinearObservations(observations(), Vector::Constant(2, std::nan("")), two), std::invalid_argument);
  const LinearObservations J(observations(), two, two);
  EXPECT_THROW(J.value(Vector::Zero(5), Vector()), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::linear_observations_test
