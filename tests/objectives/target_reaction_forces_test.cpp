#include "objectives/target_reaction_forces.hpp"

#include <gtest/gtest.h>

#include "objective_checks.hpp"
#include "../support/fem_fixtures.hpp"

namespace tailor::target_reaction_forces_test {
namespace {

using Aggregation = TargetReactionForces::Aggregation;
using testing::random_vector;

// DOFs of the vertices on the face X_0 = 0 (the clamped end of a cantilever).
std::vector<int> left_face_dofs(const Mesh& mesh) {
  std::vector<int> dofs;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (mesh.rest_positions(v, 0) == 0.0)
      for (int k = 0; k < mesh.dim(); ++k) dofs.push_back(mesh.dim() * v + k);
  return dofs;
}

struct Scene {
  Mesh mesh;
  std::shared_ptr<EnergyTerm> term;
  Vector x, p;
};

Scene make_setup(int dim) {
  Scene s;
  s.mesh = testing::small_mesh(dim);
  if (dim == 2)
    s.term = testing::elastic_term<2>(s.mesh, MaterialKind::neo_hookean);
  else
    s.term = testing::elastic_term<3>(s.mesh, MaterialKind::neo_hookean);
  // A stretched, sheared and randomly perturbed state.
  Matrix A = Matrix::Identity(dim, dim);
  A(0, 0) = 1.1;
  A(1, 0) = 0.05;
  s.x = testing::affine_state(s.mesh, A, Vector::Zero(dim)) + random_vector(dim * s.mesh.num_vertices(), 13, 0.03);
  s.p = testing::heterogeneous_parameters(s.mesh, 10.0, 0.3);
  return s;
}

class TargetReactionForcesTest : public ::testing::TestWithParam<std::tuple<int, Aggregation>> {};

TEST_P(TargetReactionForcesTest, DerivativesMatchDifferences) {
  const auto [dim, aggregation] = GetParam();
  const Scene s = make_setup(dim);
  const std::vector<int> dofs = left_face_dofs(s.mesh);
  const int m = aggregation == Aggregation::per_dof ? static_cast<int>(dofs.size()) : dim;
  const Vector target = random_vector(m, 17, 0.5);
  const Vector weights = (random_vector(m, 19).array() + 1.5).matrix();
  const TargetReactionForces J(*s.term, static_cast<int>(s.x.size()), dim, dofs, aggregation, target, weights);
  ASSERT_EQ(J.num_residuals(), m);
  ASSERT_GT(J.value(s.x, s.p), 0.0);

  const Vector dx = random_vector(s.x.size(), 23);
  const Vector dp = testing::relative_direction(s.p, 29);
  const Vector no_dx = Vector::Zero(s.x.size()), no_dp = Vector::Zero(s.p.size());
  TAILOR_EXPECT_CHECK(testing::check_gradient_x(J, s.x, s.p, dx));
  TAILOR_EXPECT_CHECK(testing::check_gradient_p(J, s.x, s.p, dp));
  TAILOR_EXPECT_CHECK(testing::check_residual_jacobians(J, s.x, s.p, dx, no_dp));
  TAILOR_EXPECT_CHECK(testing::check_residual_jacobians(J, s.x, s.p, no_dx, dp));
  testing::expect_least_squares_consistent(J, s.x, s.p);

  // Third derivatives of the energy are not available: no second derivatives, loudly.
  EXPECT_FALSE(J.has_second_derivatives());
  Vector out_x = Vector::Zero(s.x.size()), out_p = Vector::Zero(s.p.size());
  EXPECT_THROW(J.add_hessian_times(s.x, s.p, dx, dp, out_x, out_p), std::logic_error);
}

INSTANTIATE_TEST_SUITE_P(DimsAndAggregations, TargetReactionForcesTest,
                         ::testing::Combine(::testing::Values(2, 3),
                                            ::testing::Values(Aggregation::per_dof, Aggregation::total)),
                         [](const auto& param_info) {
                           return "dim" + std::to_string(std::get<0>(param_info.param)) +
                                  (std::get<1>(param_info.param) == Aggregation::total ? "_total" : "_per_dof");
                         });

TEST(TargetReactionForces, ReactionIsTheEnergyGradientOnTheSelectedDofs) {
  const Scene s = make_setup(3);
  const std::vector<int> dofs = left_face_dofs(s.mesh);
  const int n = static_cast<int>(s.x.size());
  const TargetReactionForces per_dof(s.term, n, 3, dofs, Aggregation::per_dof, Vector::Zero(dofs.size()));
  const TargetReactionForces total(s.term, n, 3, dofs, Aggregation::total, Vector::Zero(3));
  Vector f = Vector::Zero(n);
  s.term->add_gradient(s.x, s.p, f);
  const Vector y = per_dof.reaction(s.x, s.p);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < dofs.size(); ++i) {
    EXPECT_EQ(y[static_cast<Eigen::Index>(i)], f[dofs[i]]);
    sum[dofs[i] % 3] += f[dofs[i]];
  }
  EXPECT_LE((total.reaction(s.x, s.p) - sum).norm(), 1e-12 * sum.norm());
  EXPECT_GT(sum.norm(), 1e-3);  // the stretched body pulls on its support

  // Internal forces balance: the total over every vertex vanishes (translation invariance),
  // and a rigidly moved body has no reactions at all.
  std::vector<int> all(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) all[static_cast<std::size_t>(i)] = i;
  const TargetReactionForces everything(s.term, n, 3, all, Aggregation::total, Vector::Zero(3));
  EXPECT_LE(everything.reaction(s.x, s.p).norm(), 1e-10 * f.norm());
  const Vector rigid = testing::affine_state(s.mesh, testing::rotation(3, 0.4), Vector::Constant(3, 0.7));
  EXPECT_LE(per_dof.reaction(rigid, s.p).norm(), 1e-10);
}

TEST(TargetReactionForces, RejectsInvalidInput) {
  const Scene s = make_setup(2);
  const EnergyTerm& term = *s.term;
  const int n = static_cast<int>(s.x.size());
  const Vector t2 = Vector::Zero(2);
  EXPECT_THROW(TargetReactionForces(term, n, 2, {}, Aggregation::total, t2), std::invalid_argument);
  EXPECT_THROW(TargetReactionForces(term, n, 2, {0, n}, Aggregation::total, t2), std::invalid_argument);
  EXPECT_THROW(TargetReactionForces(term, n, 2, {0, -1}, Aggregation::total, t2), std::invalid_argument);
  EXPECT_THROW(TargetReactionForces(term, n, 2, {1, 1}, Aggregation::total, t2), std::invalid_argument);
  EXPECT_THROW(TargetReactionForces(term, n, 4, {0, 1}, Aggregation::total, t2), std::invalid_argument);  // n % 4
  EXPECT_THROW(TargetReactionForces(term, n, 2, {0, 1, 2}, Aggregation::per_dof, t2), std::invalid_argument);
  EXPECT_THROW(TargetReactionForces(term, n, 2, {0, 1}, Aggregation::total, t2, Vector::Ones(3)), std::invalid_argument);
  EXPECT_THROW(TargetReactionForces(term, n, 2, {0, 1}, Aggregation::total, t2, Vector::Constant(2, -1.0)),
               std::invalid_argument);
  EXPECT_THROW(TargetReactionForces(std::shared_ptr<const EnergyTerm>(), n, 2, {0, 1}, Aggregation::total, t2),
               std::invalid_argument);
  const TargetReactionForces J(term, n, 2, {0, 1}, Aggregation::total, t2);
  EXPECT_THROW(J.value(Vector::Zero(n + 2), s.p), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::target_reaction_forces_test
