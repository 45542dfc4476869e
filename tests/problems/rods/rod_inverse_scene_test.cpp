// The "inverse" section of rod scenes (tailor gradcheck / tailor run): Taylor tests of the
// shipped scenes (reference: the adjoint gradient against the second-order Taylor remainder,
// rate >= 1.9 after the first-order regime at rate ~1), recovery of known rest curvatures from
// the equilibrium they produce (reference: the truth itself), the shipped designs reaching their
// targets, and errors naming the key.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../../support/report_checks.hpp"
#include "../../support/temp_folder.hpp"
#include "problems/fem/scene.hpp"
#include "problems/rods/rod_inverse.hpp"
#include "rod_scene_files.hpp"

namespace tailor::rod_inverse_scene_test {
namespace {

using testing::read_json_file;
using testing::rod_scene_path;

std::string out_dir(const std::string& name) {
  return testing::unique_temp_path("tailor_rod_inverse_" + name).string();
}

// The "target" section that asks every vertex of the 13-vertex rod to sit where state x has it
// (x: the positions, 3 per vertex, then the twists).
nlohmann::json target_of_every_vertex(const Vector& x) {
  nlohmann::json vertices = nlohmann::json::array(), positions = nlohmann::json::array();
  for (int v = 0; v < 13; ++v) {
    vertices.push_back(v);
    positions.push_back({x[3 * v], x[3 * v + 1], x[3 * v + 2]});
  }
  return {{"vertices", vertices}, {"positions", positions}};
}

// A horizontal rod of length 1 (12 edges), EI = 1, clamped at its first edge, total weight 2
// under gravity; the rest curvatures of all interior vertices are designed.
nlohmann::json sagging_rod() {
  const double r = 1e-2, E = 4.0 / (M_PI * std::pow(r, 4)), g = 9.81, density = 2.0 / (M_PI * r * r * g);
  nlohmann::json scene = {{"rods",
                           {{{"name", "strand"},
                             {"line", {{"from", {0, 0, 0}}, {"to", {1, 0, 0}}, {"vertices", 13}}},
                             {"cross_section", {{"radius", r}}},
                             {"material", {{"youngs_modulus", E}, {"density", density}}},
                             {"clamp", {"first"}}}}},
                          {"gravity", {0, -g, 0}},
                          {"inverse", {{"design", "rest_curvature"}, {"target", "drawn"}}}};
  return scene;
}

TEST(RodInverseScene, ShippedScenesPassGradcheck) {
  for (const std::string name : {"rod_rest_shape_design.json", "rod_stiffness_design.json"}) {
    const std::string path = rod_scene_path(name);
    const auto problem = build_rod_inverse(read_json_file(path), path, "test");
    const RodGradcheck check = gradcheck_rod_scene(*problem, out_dir("gradcheck"), {}, false, nullptr);
    EXPECT_TRUE(check.passed()) << name << "\n" << check.gradient.table();
    EXPECT_GE(check.gradient.rate1, 1.9) << name << "\n" << check.gradient.table();
    EXPECT_NEAR(check.gradient.rate0, 1.0, 0.2) << name << "\n" << check.gradient.table();
    testing::expect_report_header(out_dir("gradcheck") + "/gradcheck.json");
    std::printf("%s: %d design variables, Taylor rates %.3f / %.3f\n", name.c_str(),
                static_cast<int>(problem->z0.size()), check.gradient.rate0, check.gradient.rate1);
  }
}

TEST(RodInverseScene, RecoversKnownRestCurvaturesThroughTheScene) {
  nlohmann::json scene = sagging_rod();
  const auto probe = build_rod_inverse(scene, "sagging_rod", "probe");
  const int ni = 11;
  ASSERT_EQ(probe->z0.size(), 2 * ni);
  Vector truth(2 * ni);
  for (int i = 0; i < ni; ++i) {
    const double u = (i + 1.0) / 12.0;
    truth[2 * i] = 0.05 * std::sin(M_PI * u);  // out of the plane of gravity
    truth[2 * i + 1] = 0.2 * (1.0 - u);        // curls up against gravity
  }
  probe->functional->value(truth);
  scene["inverse"]["target"] = target_of_every_vertex(probe->functional->state());
  const auto problem = build_rod_inverse(scene, "sagging_rod", "recovery");
  const RodInverseRun run = run_rod_inverse(*problem, out_dir("recovery"), nullptr, nullptr);
  const double curvature_error =
      (run.result.z - truth).lpNorm<Eigen::Infinity>() / truth.lpNorm<Eigen::Infinity>();
  std::printf("scene recovery: %d iterations, %.2f s, shape error %.2e -> %.2e, rest-curvature error %.2e\n",
              static_cast<int>(run.result.history.size()), run.result.seconds, run.initial_shape_error,
              run.shape_error, curvature_error);
  EXPECT_GT(run.initial_shape_error, 0.1);
  EXPECT_LT(run.shape_error, 1e-9) << run.result.report();
  EXPECT_LT(curvature_error, 1e-6) << run.result.report();
  testing::expect_report_header(out_dir("recovery") + "/report.json");
  EXPECT_TRUE(std::filesystem::exists(out_dir("recovery") + "/rods.vtu"));
}

// Stiffness design from a known truth: one radius for the whole rod ("per": "rod") is
// identifiable from the sag; the target is the equilibrium at r = 1.2 r0 (reference: 1.2 r0).
TEST(RodInverseScene, RecoversKnownRodRadiusThroughTheScene) {
  nlohmann::json scene = sagging_rod();
  scene["rods"][0]["point_loads"] = {{{"vertex", 12}, {"force", {0.0, -0.5, 0.2}}}};
  scene["inverse"] = {{"design", "radius"}, {"per", "rod"}};
  const auto probe = build_rod_inverse(scene, "sagging_rod", "probe");
  ASSERT_EQ(probe->z0.size(), 1);
  const Vector truth = Vector::Constant(1, std::log(1.2));
  probe->functional->value(truth);
  scene["inverse"]["target"] = target_of_every_vertex(probe->functional->state());
  const auto problem = build_rod_inverse(scene, "sagging_rod", "radius_recovery");
  const RodInverseRun run = run_rod_inverse(*problem, out_dir("radius_recovery"), nullptr, nullptr);
  const double radius_ratio = std::exp(run.result.z[0]);
  std::printf("scene radius recovery: %d iterations, shape error %.2e -> %.2e, radius %.12f r0 (truth 1.2)\n",
              static_cast<int>(run.result.history.size()), run.initial_shape_error, run.shape_error,
              radius_ratio);
  EXPECT_GT(run.initial_shape_error, 0.05);
  EXPECT_LT(run.shape_error, 1e-9) << run.result.report();
  EXPECT_NEAR(radius_ratio, 1.2, 1e-8) << run.result.report();
}

// The shipped designs: the hook's rest shape makes it hang as drawn (rest curvatures and rest
// lengths: an exact solution exists), the beam's radii give the asked tip deflection.
TEST(RodInverseScene, ShippedDesignsReachTheirTargets) {
  {
    const std::string path = rod_scene_path("rod_rest_shape_design.json");
    const auto problem = build_rod_inverse(read_json_file(path), path, "hook");
    const RodInverseRun run = run_rod_inverse(*problem, out_dir("hook"), nullptr, nullptr);
    std::printf("rest-shape design: %d iterations, %.2f s, shape error %.2e -> %.2e\n",
                static_cast<int>(run.result.history.size()), run.result.seconds, run.initial_shape_error,
                run.shape_error);
    EXPECT_TRUE(run.final_converged);
    EXPECT_GT(run.initial_shape_error, 0.05);
    EXPECT_LT(run.shape_error, 1e-8) << run.result.report();
  }
  {
    const std::string path = rod_scene_path("rod_stiffness_design.json");
    const auto problem = build_rod_inverse(read_json_file(path), path, "beam");
    const RodInverseRun run = run_rod_inverse(*problem, out_dir("beam"), nullptr, nullptr);
    problem->functional->value(run.result.z);
    const Vector& x = problem->functional->state();
    const double tip_y = x[3 * 20 + 1];
    const Vector r = problem->functional->parameters().segment(problem->model.blocks[0].radius, 20);
    std::printf(
        "stiffness design: %d iterations, %.2f s, tip deflection %.6f (target -0.02), radius %.3f .. %.3f "
        "r0\n",
        static_cast<int>(run.result.history.size()), run.result.seconds, tip_y, r[0] / 0.01, r[19] / 0.01);
    EXPECT_NEAR(tip_y, -0.02, 1e-5) << run.result.report();
    // Minimal relative change for a stiffer beam: the radii grow most near the clamp, where the
    // moment is largest (reference: the moment P (L - s) of the cantilever).
    EXPECT_GT(r[0], r[19]);
    EXPECT_GT(r.minCoeff(), 0.01 * (1.0 - 1e-9));
  }
}

TEST(RodInverseScene, BadInputNamesTheKey) {
  auto expect_error = [](nlohmann::json scene, const std::string& needle) {
    try {
      build_rod_inverse(scene, "bad", "bad");
      ADD_FAILURE() << "no error for " << needle;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  nlohmann::json s = sagging_rod();
  s["inverse"]["design"] = "stiffness";
  expect_error(s, "inverse.design");
  s = sagging_rod();
  s["inverse"]["target"] = {{"vertices", {13}}, {"positions", {{0, 0, 0}}}};
  expect_error(s, "inverse.target.vertices");
  s = sagging_rod();
  s["inverse"]["rod"] = "nope";
  expect_error(s, "inverse.rod");
  s = sagging_rod();
  s["inverse"]["design"] = {"radius", "radius"};
  expect_error(s, "given twice");
  s = sagging_rod();
  s["inverse"]["colour"] = 1;
  expect_error(s, "colour");
  s = sagging_rod();
  s.erase("inverse");
  expect_error(s, "inverse");
}

}  // namespace
}  // namespace tailor::rod_inverse_scene_test
