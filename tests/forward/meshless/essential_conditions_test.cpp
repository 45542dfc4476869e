// Essential conditions of MLS solids (forward/meshless/essential_conditions.hpp): the naive way
// (fixing the coefficients of the clamped nodes as if they were values) leaves the clamped face
// moving; the transformation holds it at the collocation points to round-off, for any free
// unknowns and in a solved cantilever. The figures are printed; docs/meshless.md quotes them.
#include "forward/meshless/essential_conditions.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "forward/fem/loads.hpp"
#include "forward/meshless/meshless_elastic_term.hpp"
#include "meshless_fixtures.hpp"

namespace tailor::essential_conditions_test {
namespace {

using namespace tailor::meshless_testing;

constexpr double kLength = 4.0;

std::vector<int> nodes_on_face(const MeshlessSolid& s, double x_value) {
  std::vector<int> out;
  for (int a = 0; a < s.num_nodes(); ++a)
    if (std::abs(s.sampling.nodes(a, 0) - x_value) < 1e-9) out.push_back(a);
  return out;
}

Eigen::MatrixXd positions_of(const MeshlessSolid& s, const std::vector<int>& nodes) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(nodes.size()), 3);
  for (std::size_t i = 0; i < nodes.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = s.sampling.nodes.row(nodes[i]);
  return out;
}

// Largest |x(X) - X| over the collocation points (the clamped nodes' rest positions) and over
// a 9 x 9 grid of other points of the face x = 0.
struct FaceMotion {
  double at_collocation = 0.0;
  double between = 0.0;
};
FaceMotion face_motion(const MeshlessSolid& s, const std::vector<int>& clamped, const Vector& x) {
  FaceMotion m;
  for (int b : clamped) {
    const Eigen::Vector3d X = s.sampling.nodes.row(b).transpose();
    m.at_collocation = std::max(m.at_collocation, (s.mls->interpolate(x, X) - X).norm());
  }
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 8; ++j) {
      const Eigen::Vector3d X(0.0, (i + 0.5) / 9.5, (j + 0.5) / 9.5);
      m.between = std::max(m.between, (s.mls->interpolate(x, X) - X).norm());
    }
  return m;
}

MeshlessSolid bar() { return make_solid(box_shape(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(kLength, 1, 1)), 0.25, 2, 0); }

TEST(MlsTransformation, HoldsTheCollocationPointsForAnyFreeUnknowns) {
  const MeshlessSolid s = bar();
  const std::vector<int> clamped = nodes_on_face(s, 0.0);
  ASSERT_EQ(clamped.size(), 25u);
  // Prescribed positions: a rigid motion of the face plus a small stretch.
  Eigen::MatrixXd targets = positions_of(s, clamped);
  for (Eigen::Index i = 0; i < targets.rows(); ++i) targets.row(i) += Eigen::RowVector3d(0.1, -0.2, 0.05 * targets(i, 1));
  const MlsEssentialConditions bc = mls_transformation(*s.mls, clamped, targets);
  EXPECT_EQ(bc.elimination.num_free(), 3 * (s.num_nodes() - 25));
  std::mt19937 rng(2);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 3; ++trial) {
    Vector y(bc.elimination.num_free());
    for (Eigen::Index i = 0; i < y.size(); ++i) y[i] = normal(rng);
    const Vector x = bc.elimination.expand(y);
    for (std::size_t i = 0; i < clamped.size(); ++i) {
      const Eigen::Vector3d X = s.sampling.nodes.row(clamped[i]).transpose();
      EXPECT_LT((s.mls->interpolate(x, X) - targets.row(static_cast<Eigen::Index>(i)).transpose()).norm(), 1e-12);
    }
  }
  // The free unknowns are the other nodes' coefficients: restrict_state recovers them.
  Vector y = Vector::Zero(bc.elimination.num_free());
  for (Eigen::Index i = 0; i < y.size(); ++i) y[i] = normal(rng);
  EXPECT_LT((bc.elimination.restrict_state(bc.elimination.expand(y)) - y).norm(), 1e-9 * y.norm());
}

TEST(MlsTransformation, RefusesRepeatedNodesAndBadTargets) {
  const MeshlessSolid s = make_solid(box_shape(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1)), 0.5, 2, 0);
  EXPECT_THROW(mls_transformation(*s.mls, {0, 0}, Eigen::MatrixXd::Zero(2, 3)), std::invalid_argument);
  EXPECT_THROW(mls_transformation(*s.mls, {0, 1}, Eigen::MatrixXd::Zero(3, 3)), std::invalid_argument);
  EXPECT_THROW(mls_transformation(*s.mls, {-1}, Eigen::MatrixXd::Zero(1, 3)), std::invalid_argument);
}

// The collocation matrix C_BB (phi_b(X_b') of the constrained nodes) is refused when it is
// singular: a second node at the position of a constrained one gives C_BB two equal rows. The
// condition estimate (Hager's, of the 1-norm) grows with the support radius, as the face's shape
// functions flatten: 3.8, 181, 8.3e3 for supports 2, 4, 12 spacings on this face.
TEST(MlsTransformation, RefusesASingularCollocationMatrix) {
  const MeshlessSolid s = make_solid(box_shape(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1)), 0.5, 2, 0);
  const std::vector<int> face = nodes_on_face(s, 0.0);
  ASSERT_EQ(face.size(), 9u);
  std::vector<double> estimates;
  for (double factor : {2.0, 4.0, 12.0}) {
    MlsOptions options;
    options.support_factor = factor;
    const MlsShapeFunctions mls(s.sampling.nodes, s.sampling.spacing, options);
    estimates.push_back(mls_transformation(mls, face, positions_of(s, face)).condition_estimate);
  }
  EXPECT_GE(estimates[0], 1.0);
  EXPECT_LT(estimates[0], 10.0);
  EXPECT_GT(estimates[1], 10.0 * estimates[0]);
  EXPECT_GT(estimates[2], 10.0 * estimates[1]);
  // The face's first node twice.
  Eigen::MatrixXd nodes(s.num_nodes() + 1, 3);
  nodes << s.sampling.nodes, s.sampling.nodes.row(face[0]);
  Eigen::VectorXd spacing(s.num_nodes() + 1);
  spacing << s.sampling.spacing, s.sampling.spacing[face[0]];
  const MlsShapeFunctions doubled(nodes, spacing);
  std::vector<int> constrained = face;
  constrained.push_back(s.num_nodes());
  Eigen::MatrixXd targets(10, 3);
  targets << positions_of(s, face), s.sampling.nodes.row(face[0]);
  try {
    mls_transformation(doubled, constrained, targets);
    ADD_FAILURE() << "a singular collocation matrix was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("singular or ill-conditioned"), std::string::npos) << e.what();
  }
}

// A bar clamped at x = 0 and loaded by a shear traction on x = L: the naive clamp lets the face
// move (by a fraction of the tip deflection that is reported), the transformation does not.
TEST(MlsTransformation, NaiveClampMovesTheFaceTransformationDoesNot) {
  const MeshlessSolid s = bar();
  const std::vector<int> clamped = nodes_on_face(s, 0.0);
  const Vector rest = s.rest();
  const Vector p = uniform_parameters(s.num_nodes(), 1000.0, 0.3);
  // Traction (0, 0, -1) on the end face: 4 x 4 cells of 2 x 2 Gauss points each.
  std::vector<double> gx, gw;
  gauss_legendre(2, gx, gw);
  Eigen::MatrixXd points(64, 3), densities(64, 3);
  Eigen::VectorXd weights(64);
  int k = 0;
  for (int ci = 0; ci < 4; ++ci)
    for (int cj = 0; cj < 4; ++cj)
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b, ++k) {
          points.row(k) << kLength, 0.25 * (ci + 0.5 * (1 + gx[static_cast<std::size_t>(a)])),
              0.25 * (cj + 0.5 * (1 + gx[static_cast<std::size_t>(b)]));
          weights[k] = 0.125 * 0.125 * gw[static_cast<std::size_t>(a)] * gw[static_cast<std::size_t>(b)];
          densities.row(k) << 0, 0, -1;
        }
  const Vector f = meshless_point_forces(*s.mls, points, weights, densities);
  auto model_with = [&](Elimination elimination) {
    auto model = std::make_unique<Model>(3 * s.num_nodes());
    model->parameter_layout().add("youngs_modulus", s.num_nodes());
    model->parameter_layout().add("poisson_ratio", s.num_nodes());
    model->add(std::make_unique<MeshlessElasticTerm<3>>(s.quadrature, make_material<3>(MaterialKind::linear), 0,
                                                        s.num_nodes()));
    model->add(std::make_unique<ExternalForceTerm>(f));
    model->set_elimination(std::move(elimination));
    return model;
  };
  std::vector<int> fixed_dofs;
  for (int b : clamped)
    for (int c = 0; c < 3; ++c) fixed_dofs.push_back(3 * b + c);
  const auto naive = model_with(Elimination::dirichlet(fixed_dofs, rest));
  const auto transformed = model_with(mls_transformation(*s.mls, clamped, positions_of(s, clamped)).elimination);
  const Vector x_naive = solve_equilibrium(*naive, p, rest), x_transformed = solve_equilibrium(*transformed, p, rest);
  const double tip = std::abs(s.mls->interpolate(x_transformed, Eigen::Vector3d(kLength, 0.5, 0.5))[2] - 0.5);
  const FaceMotion m_naive = face_motion(s, clamped, x_naive), m_ours = face_motion(s, clamped, x_transformed);
  std::printf("clamped face x = 0 of a 4 x 1 x 1 bar, h = 0.25, tip deflection %.6e\n", tip);
  std::printf("  naive:          max |u| at the clamped nodes %.3e (%.2f%% of the tip), between them %.3e\n",
              m_naive.at_collocation, 100 * m_naive.at_collocation / tip, m_naive.between);
  std::printf("  transformation: max |u| at the clamped nodes %.3e, between them %.3e\n", m_ours.at_collocation,
              m_ours.between);
  const double tip_naive = std::abs(s.mls->interpolate(x_naive, Eigen::Vector3d(kLength, 0.5, 0.5))[2] - 0.5);
  std::printf("  tip deflection naive %.6e, transformation %.6e\n", tip_naive, tip);
  // The naive clamp moves the face by a measurable 1e-4 of the tip deflection and more (the
  // coefficients' neighbours pull the field); the transformation holds it to round-off.
  EXPECT_GT(m_naive.at_collocation, 1e-4 * tip);
  EXPECT_LT(m_ours.at_collocation, 1e-12 * (1 + tip));
  EXPECT_GT(m_naive.at_collocation, 1e8 * m_ours.at_collocation);
  // Between the collocation points the field is not prescribed; it still moves less.
  EXPECT_LT(m_ours.between, m_naive.between);
}

}  // namespace
}  // namespace tailor::essential_conditions_test
