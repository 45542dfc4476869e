// MLS shape functions (forward/meshless/mls_shape_functions.hpp): partition of unity and linear
// reproduction to round-off (values and gradients), quadratic reproduction with the quadratic
// basis, gradients against central differences, the weight's continuity, and the refusal of
// points with too few covering nodes or an ill-conditioned moment matrix, named by coordinates.
#include "forward/meshless/mls_shape_functions.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "forward/meshless/meshless_quadrature.hpp"
#include "forward/meshless/octree_sampling.hpp"

namespace tailor::mls_shape_functions_test {
namespace {

struct BallSetup {
  OctreeSampling sampling;
  MlsShapeFunctions mls;
};

BallSetup ball_setup(MlsBasis basis, double factor) {
  const AnalyticShape ball = sphere_shape(Eigen::Vector3d(0, 0, 0), 1.0);
  OctreeSampling s = sample_shape(ball, {0.25, 2, 1});
  MlsOptions o;
  o.basis = basis;
  o.support_factor = factor;
  MlsShapeFunctions mls(s.nodes, s.spacing, o);
  return {std::move(s), std::move(mls)};
}

// Random quadrature points of the sampled ball (boundary cells included).
std::vector<Eigen::Vector3d> some_points(const OctreeSampling& s, int count) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(s.points.rows()) - 1);
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < count; ++i) out.push_back(s.points.row(pick(rng)).transpose());
  return out;
}

void expect_reproduction(MlsBasis basis, double factor) {
  const BallSetup setup = ball_setup(basis, factor);
  for (const Eigen::Vector3d& X : some_points(setup.sampling, 200)) {
    const MlsValues v = setup.mls.evaluate(X);
    double sum = 0.0;
    Eigen::Vector3d position = Eigen::Vector3d::Zero(), sum_gradient = Eigen::Vector3d::Zero();
    Eigen::Matrix3d identity = Eigen::Matrix3d::Zero();
    double quadratic = 0.0;                                   // sum phi_a x_a y_a
    Eigen::Vector3d quadratic_gradient = Eigen::Vector3d::Zero();
    for (std::size_t t = 0; t < v.nodes.size(); ++t) {
      const Eigen::Vector3d Xa = setup.mls.nodes().row(v.nodes[t]).transpose();
      const double phi = v.values[static_cast<Eigen::Index>(t)];
      const Eigen::Vector3d g = v.gradients.row(static_cast<Eigen::Index>(t)).transpose();
      sum += phi;
      position += phi * Xa;
      sum_gradient += g;
      identity += Xa * g.transpose();
      quadratic += phi * Xa[0] * Xa[1];
      quadratic_gradient += Xa[0] * Xa[1] * g;
    }
    EXPECT_NEAR(sum, 1.0, 1e-13) << X.transpose();
    EXPECT_LT((position - X).norm(), 1e-13) << X.transpose();
    EXPECT_LT(sum_gradient.norm(), 1e-11) << X.transpose();
    EXPECT_LT((identity - Eigen::Matrix3d::Identity()).norm(), 1e-11) << X.transpose();
    if (basis == MlsBasis::quadratic) {
      EXPECT_NEAR(quadratic, X[0] * X[1], 1e-12);
      EXPECT_LT((quadratic_gradient - Eigen::Vector3d(X[1], X[0], 0)).norm(), 1e-10);
    }
  }
}

TEST(MlsShapeFunctions, LinearBasisReproducesLinearFields) { expect_reproduction(MlsBasis::linear, 2.0); }
TEST(MlsShapeFunctions, QuadraticBasisReproducesQuadraticFields) { expect_reproduction(MlsBasis::quadratic, 3.0); }

// The linear basis does not reproduce x y: the quadratic test above can fail.
TEST(MlsShapeFunctions, LinearBasisDoesNotReproduceQuadratics) {
  const BallSetup setup = ball_setup(MlsBasis::linear, 2.0);
  double worst = 0.0;
  for (const Eigen::Vector3d& X : some_points(setup.sampling, 50)) {
    const MlsValues v = setup.mls.evaluate(X);
    double quadratic = 0.0;
    for (std::size_t t = 0; t < v.nodes.size(); ++t)
      quadratic += v.values[static_cast<Eigen::Index>(t)] * setup.mls.nodes()(v.nodes[t], 0) * setup.mls.nodes()(v.nodes[t], 1);
    worst = std::max(worst, std::abs(quadratic - X[0] * X[1]));
  }
  EXPECT_GT(worst, 1e-3);
}

TEST(MlsShapeFunctions, GradientsMatchCentralDifferences) {
  for (MlsBasis basis : {MlsBasis::linear, MlsBasis::quadratic}) {
    const BallSetup setup = ball_setup(basis, basis == MlsBasis::linear ? 2.0 : 3.0);
    const double h = 1e-6;
    for (const Eigen::Vector3d& X : some_points(setup.sampling, 40)) {
      const MlsValues v = setup.mls.evaluate(X);
      for (int k = 0; k < 3; ++k) {
        const MlsValues plus = setup.mls.evaluate(X + h * Eigen::Vector3d::Unit(k));
        const MlsValues minus = setup.mls.evaluate(X - h * Eigen::Vector3d::Unit(k));
        // Nodes entering or leaving the support have phi = 0 and grad phi = 0 there (C2 weight).
        auto value_of = [](const MlsValues& m, int node) {
          for (std::size_t t = 0; t < m.nodes.size(); ++t)
            if (m.nodes[t] == node) return m.values[static_cast<Eigen::Index>(t)];
          return 0.0;
        };
        for (std::size_t t = 0; t < v.nodes.size(); ++t) {
          const double difference = (value_of(plus, v.nodes[t]) - value_of(minus, v.nodes[t])) / (2 * h);
          EXPECT_NEAR(v.gradients(static_cast<Eigen::Index>(t), k), difference, 2e-7)
              << "node " << v.nodes[t] << " at " << X.transpose() << ", direction " << k;
        }
      }
    }
  }
}

TEST(MlsShapeFunctions, CubicSplineWeightIsC2) {
  // Values and derivatives continuous at r = 1/2 and vanishing to second order at r = 1.
  double d_lo = 0, d_hi = 0;
  const double e = 1e-9;
  EXPECT_NEAR(MlsShapeFunctions::weight(0.5 - e, &d_lo), MlsShapeFunctions::weight(0.5 + e, &d_hi), 1e-8);
  EXPECT_NEAR(d_lo, d_hi, 1e-7);
  double d = 0;
  EXPECT_NEAR(MlsShapeFunctions::weight(1.0 - 1e-4, &d), 0.0, 1e-11);
  EXPECT_NEAR(d, 0.0, 1e-7);
  EXPECT_EQ(MlsShapeFunctions::weight(1.0, &d), 0.0);
  EXPECT_NEAR(MlsShapeFunctions::weight(0.0, &d), 2.0 / 3.0, 1e-15);
  // W'(r)/r against a difference quotient.
  for (double r : {0.1, 0.3, 0.6, 0.9}) {
    MlsShapeFunctions::weight(r, &d);
    const double difference = (MlsShapeFunctions::weight(r + 1e-6, nullptr) - MlsShapeFunctions::weight(r - 1e-6, nullptr)) / 2e-6;
    EXPECT_NEAR(d * r, difference, 1e-8) << r;
  }
}

TEST(MlsShapeFunctions, RefusesAPointWithTooFewCoveringNodes) {
  const BallSetup setup = ball_setup(MlsBasis::linear, 2.0);
  const Eigen::Vector3d far(3.0, 0.25, -0.5);
  try {
    setup.mls.evaluate(far);
    FAIL() << "no error";
  } catch (const MeshlessPointError& e) {
    EXPECT_NE(std::string(e.what()).find("(3, 0.25, -0.5)"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("covered by 0 nodes"), std::string::npos) << e.what();
    EXPECT_EQ(e.point(), far);
  }
}

TEST(MlsShapeFunctions, FarAndNonFinitePointsAreRefused) {
  const BallSetup setup = ball_setup(MlsBasis::linear, 2.0);
  EXPECT_TRUE(setup.mls.covering_nodes(Eigen::Vector3d(1e300, -1e300, 0)).empty());
  EXPECT_THROW(setup.mls.evaluate(Eigen::Vector3d(1e300, 0, 0)), MeshlessPointError);
  EXPECT_THROW(setup.mls.evaluate(Eigen::Vector3d(NAN, 0, 0)), MeshlessPointError);
}

// Supports too small for the boundary cells of a sampled ball: building the quadrature stops at
// the first point that fails, naming it, instead of integrating with it.
TEST(MlsShapeFunctions, QuadratureBuildNamesTheFirstUncoveredPoint) {
  const AnalyticShape ball = sphere_shape(Eigen::Vector3d(0, 0, 0), 1.0);
  const OctreeSampling s = sample_shape(ball, {0.25, 2, 2});
  const MlsShapeFunctions mls(s.nodes, s.spacing, {MlsBasis::linear, 1.0, 1e8});
  try {
    build_meshless_quadrature(mls, s.points, s.weights);
    FAIL() << "no error";
  } catch (const MeshlessPointError& e) {
    EXPECT_NE(std::string(e.what()).find("MLS shape functions: the point ("), std::string::npos) << e.what();
    EXPECT_GT(e.point().norm(), 0.5);  // near the boundary, where the cut cells have few nodes
    EXPECT_LT(e.point().norm(), 1.0);
  }
  // With support_factor 2 every point of the same sampling is covered and well conditioned.
  const MlsShapeFunctions wide(s.nodes, s.spacing, {MlsBasis::linear, 2.0, 1e8});
  const MeshlessQuadrature q = build_meshless_quadrature(wide, s.points, s.weights);
  EXPECT_EQ(q.num_points(), s.points.rows());
  EXPECT_LT(q.max_condition, 1e8);
  std::printf("ball h = 0.25, support factor 2: largest moment-matrix condition number %.3e\n", q.max_condition);
}

TEST(MlsShapeFunctions, RefusesAnIllConditionedMomentMatrix) {
  // Nodes on the plane z = 0 only: the z column of the moment matrix vanishes.
  Eigen::MatrixXd nodes(9, 3);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) nodes.row(3 * i + j) << i, j, 0.0;
  const MlsShapeFunctions mls(nodes, Eigen::VectorXd::Constant(9, 1.0), {MlsBasis::linear, 2.0, 1e8});
  try {
    mls.evaluate(Eigen::Vector3d(1.0, 1.0, 0.1));
    FAIL() << "no error";
  } catch (const MeshlessPointError& e) {
    EXPECT_NE(std::string(e.what()).find("condition number"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("(1, 1, 0.1)"), std::string::npos) << e.what();
  }
  // Nearly planar: nodes lifted by 1e-6 make the condition finite but far above the bound.
  nodes(4, 2) = 1e-6;
  const MlsShapeFunctions nearly(nodes, Eigen::VectorXd::Constant(9, 1.0), {MlsBasis::linear, 2.0, 1e8});
  EXPECT_THROW(nearly.evaluate(Eigen::Vector3d(1.0, 1.0, 0.1)), MeshlessPointError);
}

TEST(MlsShapeFunctions, RefusesBadInput) {
  Eigen::MatrixXd nodes = Eigen::MatrixXd::Random(5, 3);
  EXPECT_THROW(MlsShapeFunctions(nodes, Eigen::VectorXd::Constant(4, 1.0)), std::invalid_argument);
  EXPECT_THROW(MlsShapeFunctions(nodes, Eigen::VectorXd::Constant(5, -1.0)), std::invalid_argument);
  nodes(2, 1) = NAN;
  EXPECT_THROW(MlsShapeFunctions(nodes, Eigen::VectorXd::Constant(5, 1.0)), std::invalid_argument);
}

}  // namespace
}  // namespace tailor::mls_shape_functions_test
