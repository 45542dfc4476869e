// Quadratic (P2) elements from the scene format ("mesh": {..., "order": 2}): exact uniaxial
// tension against Hooke's law, the edge-node rule of Dirichlet selections, a nearly
// incompressible cantilever against Timoshenko beam theory (where linear tets lock), an inverse
// design's Taylor test through the P2 adjoint, and the uses that refuse order 2.
#include <gtest/gtest.h>

#include <cmath>

#include "adjoint/scaled_gradient.hpp"
#include "adjoint/taylor_test.hpp"
#include "problems/fem/dynamic_scene.hpp"
#include "problems/fem/inverse_problem.hpp"
#include "problems/fem/modes_command.hpp"
#include "problems/fem/static_scene.hpp"
#include "scene_text.hpp"

namespace tailor::quadratic_scene_test {
namespace {

Scene parse(const std::string& text) { return parse_scene(text, "p2.json", ""); }

// small_box_scene() (2 x 1 x 1, E = 1000, nu = 0.3, unit traction along x on x = 2, supports
// that remove rigid motions only) with quadratic elements.
std::string quadratic_box() {
  return testing::with("\"cells\": [4, 2, 2]}}", "\"cells\": [4, 2, 2]}, \"order\": 2}");
}

// Reference: Hooke's law. Uniaxial stress sigma = 1 gives u = (x / E, -nu y / E, -nu z / E)
// from the vertex at the origin, a linear field that P2 elements (and their consistent loads)
// reproduce exactly.
TEST(QuadraticScene, UniaxialTensionMatchesHookesLaw) {
  const Scene scene = parse(quadratic_box());
  ASSERT_EQ(scene.mesh.order, 2);
  const StaticSetup setup = setup_static_scene(scene);
  ASSERT_TRUE(setup.quadratic);
  EXPECT_EQ(setup.num_nodes(), setup.quadratic->num_nodes());
  EXPECT_GT(setup.num_nodes(), setup.mesh.num_vertices());
  const StaticSolution solution = solve_static(setup);
  ASSERT_TRUE(solution.converged) << solution.message;
  ASSERT_EQ(solution.displacement.rows(), setup.mesh.num_vertices());  // the corners'
  const double E = 1000.0, nu = 0.3;
  for (int v = 0; v < setup.mesh.num_vertices(); ++v) {
    const Eigen::Vector3d X = setup.mesh.rest_positions.row(v).transpose();
    const Eigen::Vector3d expected(X.x() / E, -nu * X.y() / E, -nu * X.z() / E);
    EXPECT_LT((solution.displacement.row(v).transpose() - expected).norm(), 1e-10) << "vertex " << v;
  }
  // The edge nodes too: the whole state is the linear field.
  const Vector u = solution.positions - setup.rest_state();
  for (int n = 0; n < setup.num_nodes(); ++n) {
    const Eigen::Vector3d X = setup.quadratic->rest_positions.row(n).transpose();
    EXPECT_LT((u.segment<3>(3 * n) - Eigen::Vector3d(X.x() / E, -nu * X.y() / E, -nu * X.z() / E)).norm(), 1e-10)
        << "node " << n;
  }
  // Total load: traction 1 on the unit face x = 2, which the body passes on to its supports.
  EXPECT_NEAR(solution.reaction_force_total[0], 1.0, 1e-9);
}

// A plane selection holds the edge nodes between its vertices; a list of single vertices holds
// only those vertices.
TEST(QuadraticScene, DirichletSelectionsHoldEdgesBetweenSelectedVertices) {
  const StaticSetup setup = setup_static_scene(parse(quadratic_box()));
  const QuadraticMesh& q = *setup.quadratic;
  int plane_nodes = 0;
  for (int n = 0; n < q.num_nodes(); ++n) plane_nodes += std::abs(q.rest_positions(n, 0)) < 1e-12;
  std::vector<int> fixed_x, fixed_yz;
  for (int dof : setup.fixed_dofs) (dof % 3 == 0 ? fixed_x : fixed_yz).push_back(dof / 3);
  EXPECT_EQ(static_cast<int>(fixed_x.size()), plane_nodes);  // every node on x = 0, edge nodes included
  for (int n : fixed_x) EXPECT_NEAR(q.rest_positions(n, 0), 0.0, 1e-12);
  // The three single-vertex conditions: 2 + 1 + 1 components at vertices, no edge node.
  EXPECT_EQ(fixed_yz.size(), 4u);
  for (int n : fixed_yz) EXPECT_LT(n, q.num_corners());
}

// Reference: Timoshenko beam theory for a cantilever under a tip shear force F:
// w = F L^3 / (3 E I) + F L / (kappa G A), kappa = 5/6, here 1.2 + 0.0108 (L = 10, unit square
// section, E = 1e6, nu = 0.4999, F = 300). Linear tets lock: their tip moves about 1% of it.
// P2 approaches it from below as the mesh is refined (the full clamp of the 3D end face stiffens
// the root slightly against beam theory, so the last percent is not the elements' error).
TEST(QuadraticScene, NearlyIncompressibleCantileverDoesNotLock) {
  auto tip = [](int order, const std::string& cells) {
    const std::string text = R"({
      "mesh": {"box": {"min": [0, 0, 0], "max": [10, 1, 1], "cells": )" + cells + R"(}, "order": )" +
                             std::to_string(order) + R"(},
      "materials": [{"elements": "all", "model": "linear", "youngs_modulus": 1e6, "poisson_ratio": 0.4999}],
      "dirichlet": [{"vertices": {"plane": {"axis": "x", "value": 0}}}],
      "loads": {"tractions": [{"faces": {"plane": {"axis": "x", "value": 10}}, "traction": [0, 0, -300]}]}})";
    const StaticSolution s = solve_static(setup_static_scene(parse(text)));
    EXPECT_TRUE(s.converged) << s.message;
    return s.max_displacement;
  };
  const double reference = 300.0 * 1000.0 / (3.0 * 1e6 / 12.0) + 300.0 * 10.0 / (5.0 / 6.0 * 1e6 / (2.0 * 1.4999));
  const double linear = tip(1, "[20, 2, 2]");
  const double coarse = tip(2, "[10, 1, 1]"), fine = tip(2, "[20, 2, 2]");
  EXPECT_LT(linear, 0.02 * reference);
  EXPECT_LT(coarse, fine);
  EXPECT_LT(fine, reference);
  EXPECT_LT(std::abs(fine - reference), 0.06 * reference);
  EXPECT_GT(std::abs(coarse - reference), 2.0 * std::abs(fine - reference));  // converging (2.5x here)
}

// The adjoint through P2 elements from a scene: a handle design (per-element log E, the
// reaction terms of the handle's elements are quadratic too) passes the Taylor test, and a
// gradient 1% off fails it.
TEST(QuadraticScene, HandleDesignPassesTaylorTest) {
  const Scene scene = parse(R"({
    "mesh": {"box": {"min": [0, 0, 0], "max": [4, 1, 1], "cells": [4, 1, 1]}, "order": 2},
    "materials": [{"elements": "all", "model": "neo_hookean", "youngs_modulus": 1e6, "poisson_ratio": 0.45}],
    "dirichlet": [{"vertices": {"plane": {"axis": "x", "value": 0}}}],
    "inverse": {
      "design": {"parameter": "youngs_modulus", "granularity": "per_element", "map": "log"},
      "objective": [{"type": "handles", "handles": [
          {"vertices": {"box": {"min": [4, 0, 0], "max": [4, 1, 1]}}, "force": [0, 0, -2000], "displacement": [0, 0, -0.4]}]},
        {"type": "smoothness", "weight": 1e-3, "on": "log"}]}})");
  const auto problem = build_inverse_problem(scene);
  ASSERT_TRUE(problem->setup.quadratic);
  Vector z = problem->z0;
  for (Eigen::Index i = 0; i < z.size(); ++i) z[i] += 0.2 * std::sin(1.0 + 0.7 * static_cast<double>(i));
  const TaylorTestResult result = taylor_test(*problem->functional, z);
  EXPECT_TRUE(result.passed()) << result.table();
  EXPECT_GE(result.rate1, 1.9) << result.table();
  ScaledGradient corrupted(*problem->functional, 1.01);
  EXPECT_FALSE(taylor_test(corrupted, z).passed());
}

TEST(QuadraticScene, OrderOutsideOneAndTwoIsRefused) {
  for (const char* order : {"3", "0", "1.5", "\"2\""}) {
    try {
      parse(testing::with("\"cells\": [4, 2, 2]}}", std::string("\"cells\": [4, 2, 2]}, \"order\": ") + order + "}"));
      ADD_FAILURE() << "order " << order << " was accepted";
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("mesh.order"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(parse(testing::with("\"cells\": [4, 2, 2]}}", "\"cells\": [4, 2, 2]}, \"oder\": 2}")), SceneError);
}

TEST(QuadraticScene, UsesWithoutQuadraticElementsNameTheKey) {
  const Scene scene = parse(quadratic_box());
  auto expect_refusal = [](auto&& call, const char* what) {
    try {
      call();
      ADD_FAILURE() << what << " accepted quadratic elements";
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("mesh.order"), std::string::npos) << e.what();
    }
  };
  expect_refusal([&] { modes_scene(scene, 4, "unused_out"); }, "modes");
  const Scene dynamic = parse(testing::with(
      "\"solver\": {\"load_steps\": 1}",
      "\"solver\": {\"load_steps\": 1}, \"dynamics\": {\"time_step\": 0.01, \"steps\": 2}", quadratic_box()));
  expect_refusal([&] { build_dynamic_scene(dynamic); }, "dynamics");
}

}  // namespace
}  // namespace tailor::quadratic_scene_test
