#include "objectives/weighted_sum.hpp"

#include <gtest/gtest.h>

#include "objective_checks.hpp"
#include "objectives/material_smoothness.hpp"
#include "objectives/target_positions.hpp"
#include "objectives/target_reaction_forces.hpp"
#include "objectives/tikhonov.hpp"
#include "../support/fem_fixtures.hpp"

namespace tailor::weighted_sum_test {
namespace {

using testing::random_vector;

struct Scene {
  Mesh mesh;
  Vector x, p;
  ObjectivePtr positions, smoothness, tikhonov;
};

Scene make_setup(int dim) {
  Scene s;
  s.mesh = testing::small_mesh(dim);
  const int m = s.mesh.num_elements();
  s.x = testing::rest_state(s.mesh) + random_vector(dim * s.mesh.num_vertices(), 41, 0.05);
  s.p = testing::heterogeneous_parameters(s.mesh, 10.0, 0.3);
  s.positions = std::make_shared<TargetPositions>(
      TargetPositions::displacements(s.mesh, {0, 2, 5}, Matrix::Constant(3, dim, 0.1), Vector::LinSpaced(3, 1, 2)));
  s.smoothness = std::make_shared<MaterialSmoothness>(
      s.mesh, 0, 0.2, MaterialSmoothnessOptions{AdjacencyWeighting::facet_over_distance, true});
  s.tikhonov = std::make_shared<Tikhonov>(m, m, 5.0, Vector::Constant(m, 0.25));
  return s;
}

class WeightedSumTest : public ::testing::TestWithParam<int> {};

TEST_P(WeightedSumTest, CombinesThreeObjectives) {
  const Scene s = make_setup(GetParam());
  const std::vector<double> c = {2.0, 0.5, 3.0};
  const WeightedSum J({s.positions, s.smoothness, s.tikhonov}, c);
  const double expected =
      c[0] * s.positions->value(s.x, s.p) + c[1] * s.smoothness->value(s.x, s.p) + c[2] * s.tikhonov->value(s.x, s.p);
  EXPECT_NEAR(J.value(s.x, s.p), expected, 1e-14 * expected);
  EXPECT_TRUE(J.has_second_derivatives());
  ASSERT_TRUE(J.is_least_squares());
  EXPECT_EQ(J.num_residuals(),
            s.positions->num_residuals() + s.smoothness->num_residuals() + s.tikhonov->num_residuals());

  const Vector dx = random_vector(s.x.size(), 43);
  const Vector dp = testing::relative_direction(s.p, 47);
  const Vector no_dx = Vector::Zero(s.x.size()), no_dp = Vector::Zero(s.p.size());
  TAILOR_EXPECT_CHECK(testing::check_gradient_x(J, s.x, s.p, dx));
  TAILOR_EXPECT_CHECK(testing::check_gradient_p(J, s.x, s.p, dp));
  TAILOR_EXPECT_CHECK(testing::check_hessian(J, s.x, s.p, dx, no_dp));
  TAILOR_EXPECT_CHECK(testing::check_hessian(J, s.x, s.p, no_dx, dp));
  TAILOR_EXPECT_CHECK(testing::check_hessian(J, s.x, s.p, dx, dp));
  TAILOR_EXPECT_CHECK(testing::check_residual_jacobians(J, s.x, s.p, dx, dp));
  testing::expect_least_squares_consistent(J, s.x, s.p);
}

TEST_P(WeightedSumTest, WithReactionForcesHasNoSecondDerivatives) {
  const int dim = GetParam();
  const Scene s = make_setup(dim);
  std::shared_ptr<EnergyTerm> term;
  if (dim == 2)
    term = testing::elastic_term<2>(s.mesh, MaterialKind::neo_hookean);
  else
    term = testing::elastic_term<3>(s.mesh, MaterialKind::neo_hookean);
  std::vector<int> dofs;
  for (int k = 0; k < dim; ++k) dofs.push_back(k);  // vertex 0
  const auto reaction = std::make_shared<TargetReactionForces>(term, static_cast<int>(s.x.size()), dim, dofs,
                                                               TargetReactionForces::Aggregation::total,
                                                               Vector::Constant(dim, 0.3));
  const WeightedSum J({s.positions, reaction, s.tikhonov}, {1.0, 4.0, 0.5});
  EXPECT_FALSE(J.has_second_derivatives());
  EXPECT_TRUE(J.is_least_squares());
  TAILOR_EXPECT_CHECK(testing::check_gradient_x(J, s.x, s.p, random_vector(s.x.size(), 53)));
  TAILOR_EXPECT_CHECK(testing::check_gradient_p(J, s.x, s.p, testing::relative_direction(s.p, 59)));
  TAILOR_EXPECT_CHECK(testing::check_residual_jacobians(J, s.x, s.p, random_vector(s.x.size(), 61),
                                                        testing::relative_direction(s.p, 67)));
  testing::expect_least_squares_consistent(J, s.x, s.p);
  Vector out_x = Vector::Zero(s.x.size()), out_p = Vector::Zero(s.p.size());
  EXPECT_THROW(J.add_hessian_times(s.x, s.p, s.x, s.p, out_x, out_p), std::logic_error);
}

INSTANTIATE_TEST_SUITE_P(Dims, WeightedSumTest, ::testing::Values(2, 3),
                         [](const ::testing::TestParamInfo<int>& param_info) {
                           return "dim" + std::to_string(param_info.param);
                         });

TEST(WeightedSum, NegativeCoefficientIsNotLeastSquares) {
  const Scene s = make_setup(2);
  const WeightedSum J({s.positions, s.tikhonov}, {1.0, -1.0});
  EXPECT_FALSE(J.is_least_squares());
  EXPECT_EQ(J.num_residuals(), 0);
  Vector r;
  EXPECT_THROW(J.residuals(s.x, s.p, r, nullptr, nullptr), std::logic_error);
  EXPECT_NEAR(J.value(s.x, s.p), s.positions->value(s.x, s.p) - s.tikhonov->value(s.x, s.p), 1e-12);
}

TEST(WeightedSum, RejectsInvalidInput) {
  const Scene s = make_setup(2);
  EXPECT_THROW(WeightedSum({}, {}), std::invalid_argument);
  EXPECT_THROW(WeightedSum({s.positions, s.tikhonov}, {1.0}), std::invalid_argument);
  EXPECT_THROW(WeightedSum({s.positions, nullptr}, {1.0, 1.0}), std::invalid_argument);
  EXPECT_THROW(WeightedSum({s.positions}, {std::nan("")}), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::weighted_sum_test
