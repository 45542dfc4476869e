// Static scenes against analytic solutions: a bar under uniaxial tension (3D and plane
// strain), where linear elements reproduce the linear exact displacement field exactly.
#include "problems/fem/static_scene.hpp"

#include <gtest/gtest.h>

#include "scene_text.hpp"

namespace tailor::static_scene_test {
namespace {

using testing::small_box_scene;
using testing::with;

StaticSolution solve(const std::string& json, StaticSetup* setup_out = nullptr) {
  const Scene scene = parse_scene(json, "test.json", "");
  StaticSetup setup = setup_static_scene(scene);
  StaticSolution solution = solve_static(setup);
  if (setup_out) *setup_out = std::move(setup);
  return solution;
}

// Uniaxial stress sigma along x in an isotropic linear solid: u = (sigma/E) (x, -nu y, -nu z).
TEST(StaticScene, UniaxialTensionMatchesTheAnalyticDisplacement) {
  const double E = 1000.0, nu = 0.3, sigma = 1.0, L = 2.0;
  StaticSetup setup;
  const StaticSolution s = solve(small_box_scene(), &setup);
  ASSERT_TRUE(s.converged) << s.message;
  const double tip = sigma * L / E;
  double worst = 0.0;
  for (int v = 0; v < setup.mesh.num_vertices(); ++v) {
    const Eigen::Vector3d X = setup.mesh.rest_positions.row(v);
    const Eigen::Vector3d exact = sigma / E * Eigen::Vector3d(X.x(), -nu * X.y(), -nu * X.z());
    worst = std::max(worst, (s.displacement.row(v).transpose() - exact).norm());
  }
  EXPECT_LT(worst, 1e-8 * tip);
  EXPECT_NEAR(s.max_displacement, Eigen::Vector3d(tip, -nu * sigma / E, -nu * sigma / E).norm(), 1e-8 * tip);
  // The supports carry the whole load (area 1), which the body pulls on them along +x.
  EXPECT_NEAR(s.reaction_force_total[0], sigma * 1.0, 1e-8);
  EXPECT_NEAR(s.reaction_force_total[1], 0.0, 1e-8);
  EXPECT_NEAR(s.reaction_force_total[2], 0.0, 1e-8);
  // Uniform stress: P = diag(sigma, 0, 0) in every element (small strain).
  for (int e = 0; e < setup.mesh.num_elements(); ++e) {
    EXPECT_NEAR(s.stresses(e, 0), sigma, 1e-8);
    EXPECT_NEAR(s.stresses.row(e).tail(8).norm(), 0.0, 1e-8);
  }
}

TEST(StaticScene, UniaxialTensionWithoutContractionForZeroPoisson) {
  const StaticSolution s = solve(with("\"poisson_ratio\": 0.3", "\"poisson_ratio\": 0"));
  ASSERT_TRUE(s.converged) << s.message;
  const double tip = 1.0 * 2.0 / 1000.0;
  EXPECT_NEAR(s.max_displacement, tip, 1e-8 * tip);
  EXPECT_LT(s.displacement.rightCols(2).cwiseAbs().maxCoeff(), 1e-8 * tip);
}

// Plane strain (eps_zz = 0): u_x = sigma (1 - nu^2) / E x, u_y = -sigma nu (1 + nu) / E y.
TEST(StaticScene, PlaneStrainUniaxialTension) {
  const std::string scene = R"({
    "mesh": {"rectangle": {"min": [0, 0], "max": [3, 1], "cells": [6, 3]}},
    "materials": [{"elements": "all", "model": "linear", "youngs_modulus": 200, "poisson_ratio": 0.25}],
    "dirichlet": [
      {"vertices": {"plane": {"axis": "x", "value": 0}}, "components": [0]},
      {"vertices": {"list": [0]}, "components": [1]}
    ],
    "loads": {"tractions": [{"faces": {"plane": {"axis": "x", "value": 3}}, "traction": [2, 0]}]}
  })";
  const double E = 200, nu = 0.25, sigma = 2;
  StaticSetup setup;
  const StaticSolution s = solve(scene, &setup);
  ASSERT_TRUE(s.converged) << s.message;
  const double scale = sigma * 3 / E;
  for (int v = 0; v < setup.mesh.num_vertices(); ++v) {
    const Eigen::Vector2d X = setup.mesh.rest_positions.row(v);
    const Eigen::Vector2d exact(sigma * (1 - nu * nu) / E * X.x(), -sigma * nu * (1 + nu) / E * X.y());
    EXPECT_LT((s.displacement.row(v).transpose() - exact).norm(), 1e-8 * scale) << "vertex " << v;
  }
}

TEST(StaticScene, LoadStepsReachTheSameState) {
  // Neo-Hookean under a large stretch: ramping the load must end where one step ends.
  const std::string base = with("\"model\": \"linear\"", "\"model\": \"neo_hookean\"",
                                with("\"traction\": [1, 0, 0]", "\"traction\": [200, 0, 0]"));
  const StaticSolution one = solve(base);
  const StaticSolution four = solve(with("\"load_steps\": 1", "\"load_steps\": 4", base));
  ASSERT_TRUE(one.converged) << one.message;
  ASSERT_TRUE(four.converged) << four.message;
  ASSERT_EQ(four.steps.size(), 4u);
  EXPECT_DOUBLE_EQ(four.steps[1].load_factor, 0.5);
  EXPECT_LT((one.positions - four.positions).norm(), 1e-6 * one.displacement.norm());
  EXPECT_NEAR(four.reaction_force_total[0], 200.0, 1e-6 * 200.0);
}

TEST(StaticScene, PrescribedDisplacementAndNodalLoadsCompose) {
  // Stretch by a prescribed end displacement instead of a traction: u_x = d x / L.
  std::string scene = with(
      "\"tractions\": [{\"faces\": {\"plane\": {\"axis\": \"x\", \"value\": 2}}, \"traction\": [1, 0, 0]}]",
      "\"nodal\": [{\"vertices\": {\"list\": [0]}, \"force\": [0, 0, 0]}]");
  scene = with("\"dirichlet\": [",
               "\"dirichlet\": [{\"vertices\": {\"plane\": {\"axis\": \"x\", \"value\": 2}}, "
               "\"displacement\": [0.01, 0, 0], \"components\": [0]}, ",
               scene);
  StaticSetup setup;
  const StaticSolution s = solve(with("\"load_steps\": 1", "\"load_steps\": 2", scene), &setup);
  ASSERT_TRUE(s.converged) << s.message;
  for (int v = 0; v < setup.mesh.num_vertices(); ++v)
    EXPECT_NEAR(s.displacement(v, 0), 0.01 * setup.mesh.rest_positions(v, 0) / 2.0, 1e-10);
  // Both ends are supports: their forces cancel.
  EXPECT_NEAR(s.reaction_force_total[0], 0.0, 1e-8);
}

TEST(StaticScene, OneElasticTermPerMaterialEntry) {
  const std::string scene = with(
      "\"materials\": [\n    {\"elements\": \"all\", \"model\": \"linear\", \"youngs_modulus\": 1000, "
      "\"poisson_ratio\": 0.3}",
      "\"materials\": [\n    {\"elements\": {\"box\": {\"min\": [0, 0, 0], \"max\": [1, 1, 1]}}, \"model\": "
      "\"linear\", "
      "\"youngs_modulus\": 1000, \"poisson_ratio\": 0.3},\n"
      "    {\"elements\": {\"box\": {\"min\": [1, 0, 0], \"max\": [2, 1, 1]}}, \"model\": \"linear\", "
      "\"youngs_modulus\": 1000, \"poisson_ratio\": 0.3, \"density\": 5}");
  const StaticSetup setup = setup_static_scene(parse_scene(scene, "test.json", ""));
  const auto model = build_static_model(setup, 1.0);
  ASSERT_EQ(model->terms().size(), 3u);  // two elastic terms and the external force
  EXPECT_EQ(model->parameter_layout().at("youngs_modulus").size, setup.mesh.num_elements());
  EXPECT_EQ(model->parameter_layout().at("poisson_ratio").offset, setup.mesh.num_elements());
  EXPECT_EQ(setup.materials[0].elements.size() + setup.materials[1].elements.size(),
            static_cast<std::size_t>(setup.mesh.num_elements()));
  EXPECT_EQ(setup.density.maxCoeff(), 5.0);
  // Same properties on both halves: the analytic solution still holds.
  const StaticSolution s = solve_static(setup);
  ASSERT_TRUE(s.converged);
  EXPECT_NEAR(s.max_displacement, Eigen::Vector3d(2e-3, -0.3e-3, -0.3e-3).norm(), 1e-10);
}

TEST(StaticScene, NoLoadsMeansNoExternalForceTerm) {
  const std::string scene = with(
      "\"tractions\": [{\"faces\": {\"plane\": {\"axis\": \"x\", \"value\": 2}}, \"traction\": [1, 0, 0]}]",
      "");
  const StaticSetup setup = setup_static_scene(parse_scene(scene, "test.json", ""));
  EXPECT_FALSE(setup.has_loads);
  EXPECT_EQ(build_static_model(setup, 1.0)->terms().size(), 1u);
}

TEST(StaticScene, DerivativeChecksPassForEveryTerm) {
  for (const char* model : {"linear", "corotated", "stvk", "neo_hookean"}) {
    SCOPED_TRACE(model);
    const std::string scene = with("\"model\": \"linear\"", std::string("\"model\": \"") + model + "\"");
    const StaticSetup setup = setup_static_scene(parse_scene(scene, "test.json", ""));
    const std::vector<EnergyTermCheck> checks = check_static_scene(setup, 3);
    ASSERT_EQ(checks.size(), 2u);
    for (const EnergyTermCheck& c : checks) EXPECT_FALSE(check_failed(c)) << c.table();
  }
}

}  // namespace
}  // namespace tailor::static_scene_test
