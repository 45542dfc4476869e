// Smoothed, lagged IPC friction (Li et al. 2020, section 5): the smoothing f0 / f1 (f0' = f1,
// C1 at the threshold), the tangent maps of every distance branch (rigid translations and normal
// motions of the closest points are no slip), derivative checks of the friction potential for
// every pair type (point-triangle: face, edge, vertex; edge-edge: interior, endpoint-edge,
// endpoint-endpoint, mollified) in both regimes (static |u| < eps, sliding |u| > eps), over
// deformable vertices and through rigid bodies, and a deliberately wrong derivative that fails.
#include "forward/rigid/friction_term.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "adjoint/derivative_check.hpp"
#include "rigid_scenes.hpp"

namespace tailor::rigid::friction_term_test {
namespace {

using contact::PairKind;

TEST(FrictionSmoothing, F0IsC1WithDerivativeF1) {
  const double eps = 1e-3;
  for (double y : {0.0, 1e-5, 3e-4, 0.7e-3, 0.999e-3, 1e-3, 1.5e-3, 2.0}) {
    const double h = 1e-9;
    if (y > h) {
      const double fd = (contact::friction_f0(y + h, eps) - contact::friction_f0(y - h, eps)) / (2 * h);
      EXPECT_NEAR(fd, contact::friction_f1(y, eps), 1e-6) << y;
    }
  }
  EXPECT_NEAR(contact::friction_f0(eps * (1 - 1e-12), eps), eps, 1e-14);  // continuous at eps
  EXPECT_NEAR(contact::friction_f1(eps * (1 - 1e-12), eps), 1.0, 1e-9);   // C1 at eps
  EXPECT_DOUBLE_EQ(contact::friction_f0(0.0, eps), eps / 3.0);
  EXPECT_DOUBLE_EQ(contact::friction_f1(0.0, eps), 0.0);
}

// One pair over deformable vertices: 4 vertices at DOFs 0, 3, 6, 9, either a point (0) and a
// triangle (1, 2, 3) or two edges (0, 1) and (2, 3), and no rigid body.
struct DeformablePair {
  RigidBodySystem none{std::vector<RigidBody>{}};
  std::shared_ptr<const ContactBodies> bodies;
  std::unique_ptr<RigidContactTerm> contact;
  std::unique_ptr<FrictionTerm> friction;
  DeformablePair(PairKind kind, const Vector& x, double mu) {
    // Two surfaces (one group each): the point or first edge, and the triangle or second edge.
    DeformableSurface a, b;
    a.name = "a";
    b.name = "b";
    if (kind == PairKind::point_triangle) {
      a.vertex_dofs = {0};
      a.faces.resize(0, 3);
      b.vertex_dofs = {3, 6, 9};
      b.faces.resize(1, 3);
      b.faces << 0, 1, 2;
    } else {
      a.vertex_dofs = {0, 3};
      a.faces.resize(0, 3);
      a.extra_edges.resize(1, 2);
      a.extra_edges << 0, 1;
      b.vertex_dofs = {6, 9};
      b.faces.resize(0, 3);
      b.extra_edges.resize(1, 2);
      b.extra_edges << 0, 1;
    }
    bodies = std::make_shared<const ContactBodies>(none, std::vector<DeformableSurface>{a, b}, 12);
    contact::ContactOptions options;
    options.activation_distance = 0.1;
    options.stiffness = 10.0;
    contact = std::make_unique<RigidContactTerm>(bodies, x, options);
    contact::FrictionOptions f;
    f.coefficient = mu;
    f.velocity_threshold = 1e-2;  // eps = 1e-4 for h = 0.01
    friction = std::make_unique<FrictionTerm>(*contact, f);
  }
};

Vector stencil_state(std::initializer_list<double> values) {
  Vector x(12);
  int i = 0;
  for (double v : values) x[i++] = v;
  return x;
}

struct Case {
  const char* name;
  PairKind kind;
  Vector x;
  contact::DistanceBranch branch;
  bool mollified;
};

std::vector<Case> pair_cases() {
  return {
      {"point-triangle face", PairKind::point_triangle,
       stencil_state({0.2, 0.2, 0.05, 0, 0, 0, 1, 0, 0, 0, 1, 0}), contact::DistanceBranch::point_plane,
       false},
      {"point-triangle edge", PairKind::point_triangle,
       stencil_state({0.5, -0.03, 0.04, 0, 0, 0, 1, 0, 0, 0, 1, 0}), contact::DistanceBranch::point_edge,
       false},
      {"point-triangle vertex", PairKind::point_triangle,
       stencil_state({-0.03, -0.02, 0.04, 0, 0, 0, 1, 0, 0, 0, 1, 0}), contact::DistanceBranch::point_point,
       false},
      {"edge-edge interior", PairKind::edge_edge,
       stencil_state({0, 0, 0, 1, 0, 0, 0.5, -0.5, 0.05, 0.4, 0.5, 0.06}), contact::DistanceBranch::line_line,
       false},
      {"edge-edge endpoint-edge", PairKind::edge_edge,
       stencil_state({0, 0, 0, 1, 0, 0, 0.5, 0.02, 0.04, 0.6, 1, 0.5}), contact::DistanceBranch::point_edge,
       false},
      {"edge-edge endpoint-endpoint", PairKind::edge_edge,
       stencil_state({0, 0, 0, 1, 0, 0, -0.03, 0.02, 0.03, -1, 1, 0.5}), contact::DistanceBranch::point_point,
       false},
      {"edge-edge mollified", PairKind::edge_edge,
       stencil_state({0, 0, 0, 1, 0, 0, 0.2, -0.005, 0.05, 0.8, 0.005, 0.05}),
       contact::DistanceBranch::line_line, true},
  };
}

TEST(FrictionTerm, TangentMapsSeeNoSlipInTranslationsAndNormalMotion) {
  for (const Case& c : pair_cases()) {
    DeformablePair pair(c.kind, c.x, 0.5);
    pair.friction->lag(c.x, c.x, 0.01);
    ASSERT_EQ(pair.friction->pairs().size(), 1u) << c.name;
    const contact::FrictionPair& f = pair.friction->pairs()[0];
    std::array<contact::Point, 4> points;
    for (int k = 0; k < 4; ++k) points[static_cast<std::size_t>(k)] = c.x.segment<3>(3 * k);
    const contact::ClassifiedDistance distance = contact::classify_pair(c.kind, points);
    EXPECT_EQ(distance.branch, c.branch) << c.name;
    const contact::PairTangent t = contact::pair_tangent(distance, points);
    double weight_sum = 0;
    for (double w : t.weights) weight_sum += w;
    EXPECT_NEAR(weight_sum, 0.0, 1e-12) << c.name;  // closest points on the two sides
    Eigen::Matrix<double, 12, 1> translation, normal;
    for (int k = 0; k < 4; ++k) {
      translation.segment<3>(3 * k) = Eigen::Vector3d(0.3, -0.7, 0.2);
      normal.segment<3>(3 * k) = t.weights[static_cast<std::size_t>(k)] * t.normal;
    }
    EXPECT_LT((f.tangent * translation).norm(), 1e-12) << c.name;
    EXPECT_LT((f.tangent * normal).norm(), 1e-12) << c.name;
    // The tangent rows are orthonormal directions orthogonal to the normal.
    const double d = std::sqrt(distance.squared_distance);
    contact::Point r = contact::Point::Zero();
    for (int k = 0; k < 4; ++k)
      r += t.weights[static_cast<std::size_t>(k)] * points[static_cast<std::size_t>(k)];
    EXPECT_NEAR(r.norm(), d, 1e-12) << c.name;
    EXPECT_GT(f.normal_force, 0.0) << c.name;
  }
}

// Lags each pair at x, then checks the friction potential's derivatives at x + a tangential
// displacement of the first vertex below (static) and above (sliding) the threshold.
TEST(FrictionTerm, EveryPairTypePassesDerivativeChecksInBothRegimes) {
  DerivativeCheckOptions options;
  options.state_scale = 1e-6;  // perturbations far below the slip, within the branch
  for (const Case& c : pair_cases()) {
    DeformablePair pair(c.kind, c.x, 0.5);
    pair.friction->lag(c.x, c.x, 0.01);
    ASSERT_EQ(pair.friction->pairs().size(), 1u) << c.name;
    const double eps = pair.friction->threshold();
    for (double slip : {0.3 * eps, 20 * eps}) {
      Vector x = c.x;
      x.segment<3>(0) += slip * Eigen::Vector3d(0.6, 0.8, 0.0);
      x.segment<3>(6) -= 0.2 * slip * Eigen::Vector3d(0.0, 1.0, 0.0);
      const EnergyTermCheck check = check_energy_term(*pair.friction, x, Vector(), options);
      EXPECT_TRUE(check.passed()) << c.name << " slip " << slip / eps << " eps\n" << check.table();
      for (const auto& d : check.checks) EXPECT_FALSE(d.vanishing) << c.name << " " << d.quantity;
      const auto [sliding, sticking] = pair.friction->sliding_and_sticking(x);
      EXPECT_EQ(sliding, slip > eps ? 1 : 0) << c.name;
      EXPECT_EQ(sticking, slip > eps ? 0 : 1) << c.name;
    }
  }
}

// The Coulomb limit: sliding faster than the threshold, the friction force on the sliding
// vertex has magnitude mu lambda and opposes its tangential motion.
TEST(FrictionTerm, SlidingForceIsMuTimesNormalForceAgainstTheMotion) {
  const Case c = pair_cases()[0];
  const double mu = 0.4;
  DeformablePair pair(c.kind, c.x, mu);
  pair.friction->lag(c.x, c.x, 0.01);
  const double lambda = pair.friction->pairs()[0].normal_force;
  Vector x = c.x;
  const Eigen::Vector3d direction(0.6, 0.8, 0.0);
  x.segment<3>(0) += 100 * pair.friction->threshold() * direction;
  Vector g = Vector::Zero(12);
  pair.friction->add_gradient(x, Vector(), g);
  const Eigen::Vector3d force = -g.segment<3>(0);
  EXPECT_NEAR(force.norm(), mu * lambda, 1e-12 * mu * lambda);
  EXPECT_NEAR(force.normalized().dot(direction), -1.0, 1e-12);
  // The triangle receives the opposite force (Newton's third law).
  EXPECT_LT((g.segment<9>(3).reshaped(3, 3).rowwise().sum() + g.segment<3>(0)).norm(), 1e-12 * mu * lambda);
  // lambda = kappa |b'(d^2)| 2 d for the face branch (d = 0.05, d_hat = 0.1, kappa = 10).
  const double s = 0.05 * 0.05, s_hat = 0.01;
  const double b1 = -2 * (s - s_hat) * std::log(s / s_hat) - (s - s_hat) * (s - s_hat) / s;
  EXPECT_NEAR(lambda, 10.0 * std::abs(b1) * 2 * 0.05, 1e-12);
}

// Through rigid bodies: a box slightly above another, lagged, then moved sideways and turned.
TEST(FrictionTerm, RigidBoxesPassDerivativeChecksAndAWrongHessianFails) {
  const RigidBodySystem system =
      testing::box_on_ground(Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(1, 1, 1), 0.03,
                             Eigen::Vector2d(0.2, 0.05), Eigen::Vector3d(0.004, -0.006, 0.002));
  contact::ContactOptions options;
  options.activation_distance = 0.1;
  options.stiffness = 10.0;
  const RigidContactTerm contact(system, options);
  contact::FrictionOptions f;
  f.coefficient = 0.6;
  f.velocity_threshold = 1e-2;
  FrictionTerm friction(contact, f);
  const Vector q0 = system.initial_state();
  friction.lag(q0, q0, 0.01);
  EXPECT_GT(friction.pairs().size(), 4u);
  DerivativeCheckOptions check_options;
  check_options.state_scale = 1e-6;
  for (double slip : {3e-5, 2e-3}) {  // below and above eps = 1e-4 for most pairs
    Vector q = q0;
    q.segment<3>(6) += slip * Eigen::Vector3d(1.0, 0.5, 0.0);
    q.segment<3>(9) += slip * Eigen::Vector3d(0.1, -0.2, 0.7);
    const EnergyTermCheck check = check_energy_term(friction, q, Vector(), check_options);
    std::printf("%s", check.table().c_str());
    EXPECT_TRUE(check.passed()) << check.table();
  }
  // A Hessian off by 1e-4 of itself is caught.
  class Skewed final : public EnergyTerm {
   public:
    explicit Skewed(const EnergyTerm& inner) : inner_(inner) {}
    std::string name() const override { return "skewed"; }
    void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override {
      inner_.evaluate(x, p, request);
      HessianPattern pattern;
      inner_.hessian_pattern(pattern);
      if (request.hessian_values)
        for (std::size_t i = 0; i < pattern.size(); ++i) request.hessian_values[i] *= 1.0 + 1e-4;
    }
    void hessian_pattern(HessianPattern& pattern) const override { inner_.hessian_pattern(pattern); }

   private:
    const EnergyTerm& inner_;
  };
  Vector q = q0;
  q.segment<3>(6) += 2e-3 * Eigen::Vector3d(1.0, 0.5, 0.0);
  const EnergyTermCheck wrong = check_energy_term(Skewed(friction), q, Vector(), check_options);
  EXPECT_FALSE(wrong.passed()) << wrong.table();
}

}  // namespace
}  // namespace tailor::rigid::friction_term_test
