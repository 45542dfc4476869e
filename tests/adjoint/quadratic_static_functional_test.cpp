// The static adjoint through quadratic (P2) elements: Taylor tests of whole reduced functionals
// (per-element log E, tip targets) on a 10-node tet bar bent by an end traction (Neo-Hookean,
// large deformation) and on a nearly incompressible (nu = 0.4999) plane-strain strip of 6-node
// triangles. The second-order remainder must fall at rate >= 1.9 and the first-order one at ~1.
#include <gtest/gtest.h>

#include <cstdio>

#include "../support/fem_fixtures.hpp"
#include "../support/inverse_fixtures.hpp"
#include "adjoint/static_functional.hpp"
#include "adjoint/taylor_test.hpp"
#include "forward/fem/loads.hpp"
#include "forward/fem/quadratic_elastic_term.hpp"
#include "forward/fem/quadratic_loads.hpp"
#include "forward/mesh/generate.hpp"

namespace tailor::quadratic_static_functional_test {
namespace {

using namespace tailor::testing;

// A P2 body clamped at x = 0 with an end traction on x = length; design: per-element log E.
struct QuadraticProblem {
  QuadraticMesh mesh;
  std::unique_ptr<Model> model;
  Vector rest, p0;
  std::vector<int> tip_dofs;

  template <int Dim>
  static QuadraticProblem make(const Mesh& linear, MaterialKind kind, double poisson, const Eigen::VectorXd& traction) {
    QuadraticProblem q;
    q.mesh = make_quadratic_mesh(linear);
    const double length = linear.rest_positions.col(0).maxCoeff();
    const int m = q.mesh.num_elements();
    q.model = std::make_unique<Model>(Dim * q.mesh.num_nodes());
    q.model->parameter_layout().add("youngs_modulus", m);
    q.model->parameter_layout().add("poisson_ratio", m);
    q.model->add(std::make_unique<QuadraticElasticTerm<Dim>>(q.mesh, make_material<Dim>(kind), 0, m));
    const Eigen::MatrixXi end = quadratic_facets(
        q.mesh, boundary_facets_where(linear, [&](const Eigen::VectorXd& X) { return X[0] > length - 1e-9; }));
    q.model->add(std::make_unique<ExternalForceTerm>(quadratic_traction_forces(q.mesh, end, traction)));
    q.rest = quadratic_rest_state(q.mesh);
    const std::vector<int> clamped = nodes_where(q.mesh, [](const Eigen::VectorXd& X) { return X[0] < 1e-9; });
    q.model->set_elimination(Elimination::dirichlet(node_dofs(q.mesh, clamped), q.rest));
    q.tip_dofs = node_dofs(q.mesh, nodes_where(q.mesh, [&](const Eigen::VectorXd& X) { return X[0] > length - 1e-9; }));
    q.p0 = heterogeneous_parameters(linear, 1000.0, poisson);
    return q;
  }

  StaticFunctional functional(double c) {
    const int m = mesh.num_elements();
    Vector target(static_cast<Eigen::Index>(tip_dofs.size()));
    for (std::size_t k = 0; k < tip_dofs.size(); ++k) target[static_cast<Eigen::Index>(k)] = rest[tip_dofs[k]] - 0.1;
    auto map = std::make_shared<LogModuliMap>(p0, m);
    auto objective = std::make_shared<DofTargetObjective>(tip_dofs, target, c, m);
    return StaticFunctional(*model, map, objective, model->elimination().restrict_state(rest));
  }
  Vector z0() const { return p0.head(mesh.num_elements()).array().log().matrix(); }
};

void expect_taylor_rates(StaticFunctional& f, const Vector& z, const char* label) {
  const TaylorTestResult t = taylor_test(f, z);
  std::printf("%s:\n%s", label, t.table().c_str());
  EXPECT_TRUE(t.passed()) << t.table();
  EXPECT_GE(t.rate1, 1.9) << t.table();
  EXPECT_NEAR(t.rate0, 1.0, 0.1) << t.table();
}

TEST(QuadraticStaticFunctional, TaylorTestNeoHookeanTetBar) {
  QuadraticProblem bar = QuadraticProblem::make<3>(
      box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(4, 1, 1), 4, 1, 1), MaterialKind::neo_hookean, 0.3,
      Eigen::Vector3d(0, 18.0, -60.0));
  StaticFunctional f = bar.functional(1e-6);
  Vector g;
  f.value_and_gradient(bar.z0(), g);
  double tip = 0.0;
  for (int d : bar.tip_dofs) tip = std::max(tip, std::abs(f.state()[d] - bar.rest[d]));
  EXPECT_GT(tip, 0.5) << "large deformation";
  expect_taylor_rates(f, bar.z0(), "P2 Neo-Hookean tet bar, per-element log E");
}

TEST(QuadraticStaticFunctional, TaylorTestNearlyIncompressibleTriangles) {
  QuadraticProblem strip = QuadraticProblem::make<2>(
      rectangle_triangle_mesh(Eigen::Vector2d(0, 0), Eigen::Vector2d(4, 1), 8, 2), MaterialKind::linear, 0.4999,
      Eigen::Vector2d(0, -5.0));
  StaticFunctional f = strip.functional(1e-6);
  expect_taylor_rates(f, strip.z0(), "P2 plane-strain strip, nu = 0.4999, per-element log E");
}

}  // namespace
}  // namespace tailor::quadratic_static_functional_test
