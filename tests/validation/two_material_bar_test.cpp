// End-to-end inverse problem: recover the two Young's moduli of a two-material Neo-Hookean
// bar from observed displacements (synthesised from the true moduli), starting 3x off, with
// every optimizer back-end. The reference is the truth the observations came from.
#include <gtest/gtest.h>

#include <cstdio>

#include "../support/fem_fixtures.hpp"
#include "adjoint/static_functional.hpp"
#include "forward/fem/loads.hpp"
#include "objectives/target_positions.hpp"
#include "optimizers/backend_registry.hpp"
#include "optimizers/optimizer.hpp"
#include "tests/support/every_backend.hpp"

namespace tailor::two_material_bar_test {
namespace {

using namespace tailor::testing;

constexpr double kTrue[2] = {1e5, 3e5};

struct TwoMaterialBar {
  Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(4, 1, 1), 4, 1, 1);
  Model model{3 * mesh.num_vertices()};
  std::vector<int> region;
  std::vector<int> observed;
  Vector rest, base;

  TwoMaterialBar() {
    const int m = mesh.num_elements();
    model.parameter_layout().add("youngs_modulus", m);
    model.parameter_layout().add("poisson_ratio", m);
    model.add(elastic_term<3>(mesh, MaterialKind::neo_hookean));
    region.resize(m);
    for (int e = 0; e < m; ++e) {
      double cx = 0.0;
      for (int a = 0; a < 4; ++a) cx += 0.25 * mesh.rest_positions(mesh.elements(e, a), 0);
      region[e] = cx < 2.0 ? 0 : 1;
    }
    const Eigen::MatrixXi end_facets =
        boundary_facets_where(mesh, [](const Eigen::VectorXd& X) { return X[0] > 4 - 1e-9; });
    model.add(std::make_unique<ExternalForceTerm>(
        traction_forces(mesh, end_facets, Eigen::Vector3d(1e4, 0, -5e2))));
    rest = rest_state(mesh);
    std::vector<int> fixed;
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const auto X = mesh.rest_positions.row(v);
      if (X[0] < 1e-9)
        for (int k = 0; k < 3; ++k) fixed.push_back(3 * v + k);
      else if (X[1] < 1e-9 || X[1] > 1 - 1e-9 || X[2] < 1e-9 || X[2] > 1 - 1e-9)
        observed.push_back(v);  // surface vertices only: what a camera would see
    }
    model.set_elimination(Elimination::dirichlet(fixed, rest));
    base = Vector(2 * m);
    base.tail(m).setConstant(0.3);
  }

  ParameterizationPtr design_map() const {
    // z = log of the two moduli: positivity, and both moduli on one scale.
    return embed_blocks(base, {{0, compose(region_scatter_map(region, 2), exp_map(2))}});
  }
  Vector y0() const { return model.elimination().restrict_state(rest); }

  // Synthetic observations: the equilibrium under the true moduli.
  std::shared_ptr<TargetPositions> observations() const {
    Vector p = design_map()->apply(Eigen::Vector2d(std::log(kTrue[0]), std::log(kTrue[1])));
    NewtonSolver solver(model);
    Vector y = y0();
    const NewtonResult r = solver.solve(p, y);
    EXPECT_TRUE(r.converged()) << r.report();
    const Vector x = model.elimination().expand(y);
    Matrix targets(observed.size(), 3);
    for (std::size_t k = 0; k < observed.size(); ++k)
      targets.row(k) = x.segment<3>(3 * observed[k]).transpose();
    return std::make_shared<TargetPositions>(3, observed, targets);
  }
};

class TwoMaterialBarRecovery : public ::testing::TestWithParam<OptimizerBackend> {};

TEST_P(TwoMaterialBarRecovery, RecoversBothModuliFromThreeTimesOff) {
  TwoMaterialBar bar;
  StaticFunctional functional(bar.model, bar.design_map(), bar.observations(), bar.y0());
  const Vector z0 = Eigen::Vector2d(std::log(3 * kTrue[0]), std::log(kTrue[1] / 3));
  Bounds bounds;
  bounds.lower = Vector::Constant(2, std::log(1e3));
  bounds.upper = Vector::Constant(2, std::log(1e8));
  OptimizerOptions options;
  options.backend = GetParam();
  // Plain descent is the baseline: linear convergence on this ill-conditioned pair needs many
  // more (cheap, warm-started) iterations than the quasi-Newton methods.
  options.max_iterations = GetParam() == OptimizerBackend::gradient_descent ? 3000 : 500;
  options.gradient_tolerance = 1e-13;
  options.objective_tolerance = 0.0;
  const bool bounded = find_backend(GetParam()).capabilities.bounds;
  const OptimizerResult r = minimize(functional, z0, bounded ? bounds : Bounds{}, {}, options);
  const double e0 = std::exp(r.z[0]), e1 = std::exp(r.z[1]);
  std::printf("%-20s %-14s iterations %3zu  forward solves %3d  E = (%.9g, %.9g)  errors (%.1e, %.1e)\n",
              to_string(GetParam()).c_str(), to_string(r.status).c_str(), r.history.size(),
              functional.counters().forward_solves, e0, e1, std::abs(e0 / kTrue[0] - 1),
              std::abs(e1 / kTrue[1] - 1));
  EXPECT_NEAR(e0 / kTrue[0], 1.0, 1e-6) << r.report();
  EXPECT_NEAR(e1 / kTrue[1], 1.0, 1e-6) << r.report();
}

INSTANTIATE_TEST_SUITE_P(EveryBackend, TwoMaterialBarRecovery, ::testing::ValuesIn(test::every_backend()),
                         [](const auto& param_info) { return to_string(param_info.param); });

}  // namespace
}  // namespace tailor::two_material_bar_test
