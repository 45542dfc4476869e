// Closed rods in the "rods" scene section. The shipped ring scene (scenes/rods/rod_ring.json): a
// ring of radius R = 1, EI = 1, n = 64 vertices, clamped at edge 0 (midpoint at angle 0) and
// pinched by P = 1e-3 towards the centre at the midpoint of the opposite edge. By symmetry the
// load points of a ring pinched along a diameter do not rotate, so the clamp acts as the pinched
// ring's other load point; the reference is the thin-ring deflection along the load line
// (Castigliano; Roark's Formulas for Stress and Strain, table 9.2 case 1):
//   delta = (pi / 4 - 2 / pi) P R^3 / EI = 0.14878 P R^3 / EI.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../../support/temp_folder.hpp"
#include "problems/fem/scene.hpp"
#include "problems/rods/rod_scene.hpp"
#include "rod_scene_files.hpp"

namespace tailor::rod_ring_scene_test {
namespace {

using testing::read_rod_scene;

// The shipped ring with n vertices (the clamp at edge 0, the load on edge n / 2).
nlohmann::json ring_with(int n) {
  nlohmann::json s = read_rod_scene("rod_ring.json");
  auto& r = s["rods"][0];
  r["circle"]["vertices"] = n;
  r["circle"]["start_angle"] = -M_PI / n;
  r["point_loads"] = {{{"vertex", n / 2}, {"force", {0.0005, 0, 0}}},
                      {{"vertex", n / 2 + 1}, {"force", {0.0005, 0, 0}}}};
  return s;
}

// x displacement of the midpoint of edge n / 2, the load point.
double pinch_deflection(const nlohmann::json& scene) {
  const RodSceneSpec spec = parse_rod_scene(scene);
  const int n = static_cast<int>(spec.rods[0].points.rows()), a = n / 2, b = n / 2 + 1;
  const auto dir = testing::unique_temp_path("tailor_rod_ring_" + std::to_string(n));
  const RodSimulation sim = simulate_rods(spec, dir.string());
  EXPECT_TRUE(sim.converged) << n;
  EXPECT_TRUE(std::filesystem::exists(sim.vtu_path));
  std::filesystem::remove_all(dir);
  const double before = 0.5 * (spec.rods[0].points(a, 0) + spec.rods[0].points(b, 0));
  return 0.5 * (sim.state[3 * a] + sim.state[3 * b]) - before;
}

TEST(RodRingScene, PinchedRingMatchesThinRingTheory) {
  const double reference = (M_PI / 4.0 - 2.0 / M_PI) * 1e-3;  // P R^3 / EI = 1e-3
  const RodSceneSpec spec = parse_rod_scene(read_rod_scene("rod_ring.json"));
  ASSERT_TRUE(spec.rods[0].closed);
  ASSERT_EQ(spec.rods[0].points.rows(), 64);
  const double e32 = std::abs(pinch_deflection(ring_with(32)) / reference - 1.0);
  const double e64 = std::abs(pinch_deflection(read_rod_scene("rod_ring.json")) / reference - 1.0);
  std::printf("pinched ring: relative deflection errors at n = 32, 64: %.3e %.3e\n", e32, e64);
  EXPECT_LT(e64, 1e-2);
  EXPECT_GT(std::log2(e32 / e64), 1.5);
}

// closing_twist: the rest twist of every stencil is lowered by closing_twist / n, and
// rest_shape "straight" zeroes the rest curvatures (Michell's ring, tests/forward/rods).
TEST(RodRingScene, ClosingTwistAndStraightRestShape) {
  nlohmann::json s = read_rod_scene("rod_ring.json");
  s["rods"][0]["closing_twist"] = 2.0 * M_PI;
  s["rods"][0]["rest_shape"] = "straight";
  const RodSceneModel m = build_rod_model(parse_rod_scene(s));
  const RodParameterBlocks& b = m.blocks[0];
  EXPECT_EQ(m.rods[0]->num_interior(), 64);
  for (int i = 0; i < 64; ++i) {
    EXPECT_NEAR(m.p[b.rest_twist + i], -2.0 * M_PI / 64, 1e-14);
    EXPECT_EQ(m.p[b.rest_curvature + 2 * i], 0.0);
    EXPECT_EQ(m.p[b.rest_curvature + 2 * i + 1], 0.0);
  }
}

TEST(RodRingScene, BadClosedRodKeysNameTheKey) {
  auto expect_error = [](const nlohmann::json& scene, const std::string& key) {
    try {
      parse_rod_scene(scene);
      ADD_FAILURE() << "expected an error naming " << key;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  nlohmann::json s = read_rod_scene("rod_ring.json");
  s["rods"][0]["clamp"] = {"first"};
  expect_error(s, "rods[0].clamp");
  s = read_rod_scene("rod_ring.json");
  s["rods"][0]["closed"] = false;
  s["rods"][0]["closing_twist"] = 1.0;
  expect_error(s, "rods[0].closing_twist");
  s = read_rod_scene("rod_ring.json");
  s["rods"][0]["clamp_edges"] = {64};
  expect_error(s, "rods[0].clamp_edges");
  s = read_rod_scene("rod_ring.json");
  s["rods"][0]["rest_shape"] = "bent";
  expect_error(s, "rods[0].rest_shape");
  s = read_rod_scene("rod_ring.json");
  s["rods"][0]["circle"].erase("radius");
  expect_error(s, "rods[0].circle");
  s = read_rod_scene("rod_ring.json");
  s["rods"][0]["closed"] = "yes";
  expect_error(s, "rods[0].closed");
}

}  // namespace
}  // namespace tailor::rod_ring_scene_test
