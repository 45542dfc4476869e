// Rest-curvature design through the static adjoint (adjoint/static_functional.hpp): find the
// rest curvatures of a clamped rod so that under gravity it settles into a target shape.
// Taylor test of the reduced gradient (first-order remainder at rate ~1, second-order at >= 1.9)
// and recovery of a known truth (the target is the equilibrium of known rest curvatures).
#include <gtest/gtest.h>

#include <cmath>

#include "adjoint/parameterization.hpp"
#include "adjoint/static_functional.hpp"
#include "adjoint/taylor_test.hpp"
#include "forward/core/elimination.hpp"
#include "forward/fem/loads.hpp"
#include "forward/rods/rod_supports.hpp"
#include "objectives/target_positions.hpp"
#include "optimizers/optimizer.hpp"
#include "rod_fixtures.hpp"

namespace tailor {
namespace {

using namespace tailor::testing;

// A horizontal rod of length 1 (n edges) clamped at its first edge, EI = 1 (r = 1e-2), total
// weight 2 (gravity along -y): it sags by ~ W L^3 / (8 EI) = 0.25.
struct SaggingRod {
  RodSetup s;
  int n;
  explicit SaggingRod(int edges) : n(edges) {
    RodMaterial m;
    m.radius = 1e-2;
    m.youngs_modulus = 4.0 / (M_PI * std::pow(m.radius, 4));
    m.shear_modulus = m.youngs_modulus / 2.6;
    s = make_rod(straight(n + 1, 1.0), m, Eigen::Vector3d::UnitZ());
    const Eigen::VectorXd radius = Eigen::VectorXd::Constant(n, m.radius);
    const double area = M_PI * m.radius * m.radius, g = 9.81, density = 2.0 / (area * 1.0 * g);
    const Eigen::VectorXd masses =
        lumped_vertex_masses(*s.rod, m.section, density, radius, s.rod->rest_lengths());
    Vector forces = Vector::Zero(s.model->num_dofs());
    add_gravity_forces(*s.rod, masses, Eigen::Vector3d(0.0, -g, 0.0), forces);
    s.model->add(std::make_unique<ExternalForceTerm>(forces, "gravity"));
    s.model->set_elimination(Elimination::dirichlet(clamped_end_dofs(*s.rod, RodEnd::first), s.rest));
  }
  int curvature_offset() const { return s.blocks.rest_curvature; }
  int num_curvatures() const { return 2 * s.rod->num_interior(); }
  ParameterizationPtr design_map() const {
    return embed_blocks(s.p, {{curvature_offset(), identity_map(num_curvatures())}});
  }
  Vector rest_y() const { return s.model->elimination().restrict_state(s.rest); }
  // Equilibrium for rest curvatures z.
  Vector equilibrium(const Vector& z) const {
    Vector p = design_map()->apply(z);
    NewtonSolver newton(*s.model);
    Vector y = rest_y();
    const NewtonResult r = newton.solve(p, y);
    EXPECT_TRUE(r.converged()) << r.report();
    return s.model->state(y, p);
  }
  ObjectivePtr target(const Vector& x) const {
    std::vector<int> vertices;
    Matrix targets(n + 1, 3);
    for (int v = 0; v <= n; ++v) {
      vertices.push_back(v);
      targets.row(v) = s.rod->position(x, v).transpose();
    }
    return std::make_shared<TargetPositions>(3, vertices, targets);
  }
  Vector truth() const {
    Vector z(num_curvatures());
    for (int i = 0; i < s.rod->num_interior(); ++i) {
      const double u = (i + 1.0) / n;
      z[2 * i] = 0.02 * std::sin(M_PI * u);  // out of the plane of gravity
      z[2 * i + 1] = 0.15 * (1.0 - u);       // in the plane: curls up against gravity
    }
    return z;
  }
};

TEST(RodInverse, RestCurvatureGradientPassesTaylorTest) {
  SaggingRod rod(12);
  StaticFunctional f(*rod.s.model, rod.design_map(), rod.target(rod.equilibrium(rod.truth())), rod.rest_y());
  const Vector z0 = 0.5 * rod.truth();
  const TaylorTestResult t = taylor_test(f, z0);
  EXPECT_TRUE(t.passed()) << t.table();
  EXPECT_GE(t.rate1, 1.9) << t.table();
  EXPECT_NEAR(t.rate0, 1.0, 0.2) << t.table();
  std::printf("rest-curvature Taylor test: rate0 %.3f, rate1 %.3f\n", t.rate0, t.rate1);
}

TEST(RodInverse, RecoversKnownRestCurvatures) {
  SaggingRod rod(12);
  const Vector truth = rod.truth();
  const Vector target_state = rod.equilibrium(truth);
  StaticFunctional f(*rod.s.model, rod.design_map(), rod.target(target_state), rod.rest_y());
  OptimizerOptions o;
  o.backend = OptimizerBackend::ceres_least_squares;
  o.max_iterations = 100;
  o.gradient_tolerance = 1e-14;
  const OptimizerResult r = minimize(f, Vector::Zero(truth.size()), Bounds{}, {}, o);
  const Vector x = rod.equilibrium(r.z);
  double shape_error = 0.0;
  for (int v = 0; v <= rod.n; ++v)
    shape_error =
        std::max(shape_error, (rod.s.rod->position(x, v) - rod.s.rod->position(target_state, v)).norm());
  const double curvature_error = (r.z - truth).lpNorm<Eigen::Infinity>() / truth.lpNorm<Eigen::Infinity>();
  std::printf("rest-curvature recovery: %d iterations, %.2f s, max vertex error %.2e, curvature error %.2e\n",
              static_cast<int>(r.history.size()), r.seconds, shape_error, curvature_error);
  EXPECT_LT(shape_error, 1e-8) << r.report();
  EXPECT_LT(curvature_error, 1e-6) << r.report();
}

}  // namespace
}  // namespace tailor
