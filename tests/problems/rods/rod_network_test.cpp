// Rod networks: rods joined by pinned joints (shared position, free rotation) in one scene. The
// shipped scene scenes/rods/rod_frame.json is a symmetric two-bar frame: bars of length L = 1
// from clamped bases at (-0.6, 0) and (0.6, 0) to an apex at (0, 0.8), EI = 1, EA = 4e4, pinned
// together at the apex, which carries a vertical load P = 1e-4. Reference (linear frame
// analysis, by hand): by symmetry the pin passes a force (H, -P/2) to the left bar and (-H, -P/2)
// to the right one, and no moment; the left bar's tip, a cantilever with axial compliance L / EA
// along its axis e and bending compliance L^3 / (3 EI) normal to it (n), moves by
//   u = (F . e) L / EA e + (F . n) L^3 / (3 EI) n,   F = (H, -P/2),
// and symmetry asks u_x = 0, which fixes H; the apex deflection is u_y. A rigid joint would
// differ: it would hold the bars' tip rotations equal, which by symmetry are opposite.
// The bars use the staggered clamp of tests/forward/rods (the clamped edge centred on the base);
// their last vertex is the apex, so the free end is at a vertex: first order in h.
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

namespace tailor::rod_network_test {
namespace {

using testing::read_rod_scene;

// The frame with n edges per bar (n + 1 vertices, the first edge centred on the base).
nlohmann::json frame_with(int n) {
  nlohmann::json s = read_rod_scene("rod_frame.json");
  const double h = 1.0 / (n - 0.5);
  const double base[2] = {-0.6, 0.6}, ex[2] = {0.6, -0.6};
  for (int k = 0; k < 2; ++k) {
    auto& line = s["rods"][static_cast<std::size_t>(k)]["line"];
    line["from"] = {base[k] - 0.5 * h * ex[k], -0.5 * h * 0.8, 0.0};
    line["vertices"] = n + 1;
  }
  s["rods"][0]["point_loads"][0]["vertex"] = n;
  return s;
}

Eigen::Vector2d frame_reference(double P) {
  const double ca = 1.0 / 4e4, cb = 1.0 / 3.0;  // L / EA, L^3 / (3 EI)
  const Eigen::Vector2d e(0.6, 0.8), nrm(-0.8, 0.6);
  auto tip = [&](double H) {
    const Eigen::Vector2d F(H, -0.5 * P);
    return Eigen::Vector2d(F.dot(e) * ca * e + F.dot(nrm) * cb * nrm);
  };
  // u_x is linear in H: solve u_x(H) = 0.
  const double u0 = tip(0.0).x(), slope = tip(1.0).x() - u0;
  return tip(-u0 / slope);
}

// The apex displacement (x, y) of the frame scene, and that the joint held.
Eigen::Vector2d apex_displacement(const nlohmann::json& scene, int n) {
  const RodSceneSpec spec = parse_rod_scene(scene);
  const auto dir = testing::unique_temp_path("tailor_rod_frame_" + std::to_string(n));
  const RodSimulation sim = simulate_rods(spec, dir.string());
  EXPECT_TRUE(sim.converged);
  std::filesystem::remove_all(dir);
  const int left = 3 * n, right = 3 * (2 * n + 1);  // last vertex of each rod (positions first)
  EXPECT_NEAR((sim.state.segment<3>(left) - sim.state.segment<3>(right)).norm(), 0.0, 1e-15);
  return {sim.state[left], sim.state[left + 1] - 0.8};
}

TEST(RodNetwork, PinnedTwoBarFrameMatchesFrameAnalysis) {
  const Eigen::Vector2d reference = frame_reference(1e-4);
  std::vector<double> errors;
  for (int n : {10, 20, 40}) {
    const Eigen::Vector2d u =
        apex_displacement(n == 20 ? read_rod_scene("rod_frame.json") : frame_with(n), n);
    EXPECT_LT(std::abs(u.x()), 1e-6 * std::abs(reference.y()));  // symmetric
    errors.push_back(std::abs(u.y() / reference.y() - 1.0));
  }
  std::printf(
      "pinned two-bar frame: apex deflection %.6e (reference); relative errors at n = 10, 20, 40: "
      "%.3e %.3e %.3e\n",
      reference.y(), errors[0], errors[1], errors[2]);
  // First order: the bars end at a vertex (the joint), not at an edge midpoint, and the error is
  // h / (2 L) to two digits (5.26e-2, 2.56e-2, 1.27e-2); a wrong joint (rigid, or none) would
  // converge to another deflection and the errors would stop halving.
  for (std::size_t i = 1; i < errors.size(); ++i) EXPECT_GT(std::log2(errors[i - 1] / errors[i]), 0.95);
  EXPECT_LT(errors.back(), 1.5e-2);
}

// Without the joint the loaded bar is a lone cantilever: the deflection is far from the frame's.
TEST(RodNetwork, WithoutTheJointTheAnswerIsDifferent) {
  nlohmann::json s = read_rod_scene("rod_frame.json");
  s.erase("joints");
  const Eigen::Vector2d reference = frame_reference(1e-4);
  const RodSceneSpec spec = parse_rod_scene(s);
  const auto dir = testing::unique_temp_path("tailor_rod_frame_free");
  const RodSimulation sim = simulate_rods(spec, dir.string());
  std::filesystem::remove_all(dir);
  EXPECT_GT(std::abs((sim.state[3 * 20 + 1] - 0.8) / reference.y() - 1.0), 0.5);
}

TEST(RodNetwork, BadJointsNameTheKey) {
  auto expect_error = [](const nlohmann::json& scene, const std::string& key) {
    try {
      parse_rod_scene(scene);
      ADD_FAILURE() << "expected an error naming " << key;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  nlohmann::json s = read_rod_scene("rod_frame.json");
  s["joints"][0]["rods"][1]["vertex"] = 0;  // not at the apex
  expect_error(s, "joints[0].rods[1]");
  s = read_rod_scene("rod_frame.json");
  s["joints"][0]["type"] = "welded";
  expect_error(s, "joints[0].type");
  s = read_rod_scene("rod_frame.json");
  s["joints"][0]["rods"][1]["rod"] = "middle";
  expect_error(s, "joints[0].rods[1].rod");
  s = read_rod_scene("rod_frame.json");
  s["joints"][0]["rods"].erase(1);
  expect_error(s, "joints[0].rods");
  s = read_rod_scene("rod_frame.json");
  s["joints"][0]["rods"][1]["rod"] = "left";
  expect_error(s, "joints[0].rods[1]");
}

}  // namespace
}  // namespace tailor::rod_network_test
