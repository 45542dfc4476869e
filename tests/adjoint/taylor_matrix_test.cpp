// Taylor tests of whole reduced functionals for every objective x parameterization pair on a
// linear, a Neo-Hookean and a large-deformation Neo-Hookean scene: the second-order remainder
// must fall at rate >= 1.9 (adjoint gradients through Newton, parameterizations and objective
// partial derivatives all exact).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>

#include "../support/fem_fixtures.hpp"
#include "adjoint/static_functional.hpp"
#include "adjoint/taylor_test.hpp"
#include "forward/fem/loads.hpp"
#include "objectives/material_smoothness.hpp"
#include "objectives/target_positions.hpp"
#include "objectives/target_reaction_forces.hpp"
#include "objectives/tikhonov.hpp"
#include "objectives/weighted_sum.hpp"

namespace tailor::taylor_matrix_test {
namespace {

using namespace tailor::testing;

struct Scene {
  std::string name;
  MaterialKind material;
  double load;
};

struct Bar {
  Mesh mesh = box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(4, 1, 1), 4, 1, 1);
  Model model{3 * mesh.num_vertices()};
  Vector rest, p0, centroid_x;
  std::vector<int> clamped_dofs, tip_vertices;
  int m = mesh.num_elements();

  explicit Bar(const Scene& scene) {
    model.parameter_layout().add("youngs_modulus", m);
    model.parameter_layout().add("poisson_ratio", m);
    model.add(elastic_term<3>(mesh, scene.material));
    const Eigen::MatrixXi end_facets = boundary_facets_where(mesh, [](const Eigen::VectorXd& X) { return X[0] > 4 - 1e-9; });
    model.add(std::make_unique<ExternalForceTerm>(
        traction_forces(mesh, end_facets, Eigen::Vector3d(0.2 * scene.load, 0.3 * scene.load, -scene.load))));
    rest = rest_state(mesh);
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (mesh.rest_positions(v, 0) < 1e-9)
        for (int k = 0; k < 3; ++k) clamped_dofs.push_back(3 * v + k);
      if (mesh.rest_positions(v, 0) > 4 - 1e-9) tip_vertices.push_back(v);
    }
    model.set_elimination(Elimination::dirichlet(clamped_dofs, rest));
    p0 = heterogeneous_parameters(mesh, 1000.0, 0.3);
    centroid_x.resize(m);
    for (int e = 0; e < m; ++e) {
      centroid_x[e] = 0.0;
      for (int a = 0; a < 4; ++a) centroid_x[e] += 0.25 * mesh.rest_positions(mesh.elements(e, a), 0);
    }
  }
  Vector y0() const { return model.elimination().restrict_state(rest); }
};

// A parameterization with its starting design.
struct Design {
  std::string name;
  std::function<std::pair<ParameterizationPtr, Vector>(const Bar&)> make;
};

std::vector<Design> designs() {
  return {
      {"identity", [](const Bar& b) { return std::pair{embed_blocks(b.p0, {{0, identity_map(b.m)}}), Vector(b.p0.head(b.m))}; }},
      {"exp", [](const Bar& b) {
         return std::pair{embed_blocks(b.p0, {{0, exp_map(b.m)}}), Vector(b.p0.head(b.m).array().log().matrix())};
       }},
      {"linear_basis", [](const Bar& b) {
         Matrix basis(b.m, 3);
         basis.col(0).setConstant(1000.0);
         basis.col(1) = 1000.0 * b.centroid_x;
         basis.col(2) = 1000.0 * b.centroid_x.array().square().matrix();
         return std::pair{embed_blocks(b.p0, {{0, linear_basis_map(basis, Vector::Zero(b.m))}}), Vector(Eigen::Vector3d(1.0, 0.1, -0.01))};
       }},
      {"region_scatter", [](const Bar& b) {
         std::vector<int> region(b.m);
         for (int e = 0; e < b.m; ++e) region[e] = b.centroid_x[e] < 2.0 ? 0 : 1;
         return std::pair{embed_blocks(b.p0, {{0, region_scatter_map(region, 2)}}), Vector(Eigen::Vector2d(1000, 1500))};
       }},
      {"bounds", [](const Bar& b) {
         const Vector lo = Vector::Constant(b.m, 100.0), hi = Vector::Constant(b.m, 1e4);
         const Vector z = ((2.0 * (b.p0.head(b.m) - lo).array() / (hi - lo).array()) - 1.0).atanh().matrix();
         return std::pair{embed_blocks(b.p0, {{0, bounds_map(lo, hi)}}), z};
       }},
      {"spline", [](const Bar& b) {
         return std::pair{embed_blocks(b.p0, {{0, spline_map(Eigen::Vector3d(0, 2, 4), b.centroid_x)}}),
                          Vector(Eigen::Vector3d(1000, 1300, 900))};
       }},
      {"two_blocks", [](const Bar& b) {
         // log E per element, and nu per region through bounds (0.1, 0.45), composed.
         std::vector<int> region(b.m);
         for (int e = 0; e < b.m; ++e) region[e] = b.centroid_x[e] < 2.0 ? 0 : 1;
         auto nu = compose(region_scatter_map(region, 2), bounds_map(Vector::Constant(2, 0.1), Vector::Constant(2, 0.45)));
         Vector z(b.m + 2);
         z.head(b.m) = b.p0.head(b.m).array().log().matrix();
         z.tail(2) = Eigen::Vector2d(0.2, -0.3);
         return std::pair{embed_blocks(b.p0, {{0, exp_map(b.m)}, {b.m, nu}}), z};
       }},
  };
}

struct Goal {
  std::string name;
  std::function<ObjectivePtr(const Bar&)> make;
};

std::vector<Goal> goals() {
  auto positions = [](const Bar& b) {
    Matrix u(b.tip_vertices.size(), 3);
    u.rowwise() = Eigen::RowVector3d(0.05, 0.1, -0.4);
    return std::make_shared<TargetPositions>(TargetPositions::displacements(b.mesh, b.tip_vertices, u));
  };
  return {
      {"target_positions", [=](const Bar& b) -> ObjectivePtr { return positions(b); }},
      {"reaction_forces", [](const Bar& b) -> ObjectivePtr {
         // Per-DOF reactions at the clamp: their distribution depends on the stiffness field
         // (their total does not: it balances the load).
         return std::make_shared<TargetReactionForces>(*b.model.terms()[0], b.model.num_dofs(), 3, b.clamped_dofs,
                                                       TargetReactionForces::Aggregation::per_dof,
                                                       Vector::Constant(static_cast<int>(b.clamped_dofs.size()), 0.5));
       }},
      {"smoothness_log", [](const Bar& b) -> ObjectivePtr {
         MaterialSmoothnessOptions o;
         o.logarithmic = true;
         return std::make_shared<MaterialSmoothness>(b.mesh, 0, 1.0, o);
       }},
      {"tikhonov", [](const Bar& b) -> ObjectivePtr {
         return std::make_shared<Tikhonov>(0, b.m, 1e-3, Vector::Constant(b.m, 800.0));
       }},
      {"weighted_sum", [=](const Bar& b) -> ObjectivePtr {
         return std::make_shared<WeightedSum>(
             std::vector<ObjectivePtr>{positions(b), std::make_shared<MaterialSmoothness>(b.mesh, 0, 1e-6),
                                       std::make_shared<Tikhonov>(0, b.m, 1e-6, Vector::Constant(b.m, 800.0))},
             std::vector<double>{1.0, 0.5, 2.0});
       }},
  };
}

class TaylorMatrix : public ::testing::TestWithParam<Scene> {};

TEST_P(TaylorMatrix, EveryObjectiveAndParameterizationPasses) {
  std::printf("%-18s %-16s %-14s %8s %8s  %s\n", "scene", "objective", "design", "rate0", "rate1", "status");
  for (const Design& design : designs()) {
    for (const Goal& goal : goals()) {
      Bar bar(GetParam());
      auto [map, z0] = design.make(bar);
      StaticFunctional f(bar.model, map, goal.make(bar), bar.y0());
      const TaylorTestResult t = taylor_test(f, z0);
      std::printf("%-18s %-16s %-14s %8.3f %8.3f  %s\n", GetParam().name.c_str(), goal.name.c_str(),
                  design.name.c_str(), t.rate0, t.rate1, to_string(t.status).c_str());
      EXPECT_TRUE(t.passed()) << goal.name << " x " << design.name << "\n" << t.table();
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, TaylorMatrix,
                         ::testing::Values(Scene{"linear", MaterialKind::linear, 20.0},
                                           Scene{"neo_hookean", MaterialKind::neo_hookean, 20.0},
                                           Scene{"neo_hookean_large", MaterialKind::neo_hookean, 60.0}),
                         [](const auto& param_info) { return param_info.param.name; });

}  // namespace
}  // namespace tailor::taylor_matrix_test
