// The elastica through the scene parser (docs/rods.md, "Second order from a scene"): a `line`
// rod clamped at its first end under a dead tip load, alpha = P L^2 / EI = 5, against the
// elliptic-integral elastica (Bisshopp & Drucker 1945, tests/forward/rods/elastica.hpp). With
// "ends": "edge_midpoints" the clamped edge straddles the support and the tip load is split
// over the last edge (the staggered set-up of tests/forward/rods/rod_validation_test.cpp):
// second order. With the ends at vertices (the default) the clamp is the whole first edge, so
// the bending rod starts half an edge late: first order.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "../../support/temp_folder.hpp"
#include "problems/rods/rod_scene.hpp"
#include "tests/forward/rods/elastica.hpp"

namespace tailor::rod_elastica_scene_test {
namespace {

constexpr double kAlpha = 5.0;    // tip rotation ~60 degrees, deflection ~0.71 L
constexpr double kRadius = 3e-3;  // axial strain ~1e-5, far below the discretization error

// A cantilever of length 1 along +x, EI = 1 (I = pi r^4 / 4), n edges inside [0, 1], the load
// P = alpha along -y at the last end, written as a scene would be.
nlohmann::json cantilever_scene(int n, bool staggered) {
  const double E = 4.0 / (M_PI * std::pow(kRadius, 4));
  nlohmann::json rod = {
      {"line", {{"from", {0, 0, 0}}, {"to", {1, 0, 0}}, {"vertices", staggered ? n + 2 : n + 1}}},
      {"cross_section", {{"radius", kRadius}}},
      {"material", {{"youngs_modulus", E}}},
      {"clamp", {"first"}},
      {"point_loads", {{{"end", "last"}, {"force", {0.0, -kAlpha, 0.0}}}}}};
  if (staggered) rod["ends"] = "edge_midpoints";
  return {{"rods", {rod}}, {"max_newton_iterations", 200}};
}

// Tip position error / L: the tip is the last edge's midpoint (staggered) or the last vertex.
double tip_error(int n, bool staggered) {
  const RodSceneSpec spec = parse_rod_scene(cantilever_scene(n, staggered), "elastica.json");
  const auto dir = testing::unique_temp_path("tailor_rod_elastica");
  const RodSimulation sim = simulate_rods(spec, dir.string());
  std::filesystem::remove_all(dir);
  EXPECT_TRUE(sim.converged) << "n = " << n;
  const int nv = static_cast<int>(spec.rods[0].points.rows());
  auto vertex = [&](int v) { return Eigen::Vector3d(sim.state.segment<3>(3 * v)); };
  const Eigen::Vector3d tip =
      staggered ? Eigen::Vector3d(0.5 * (vertex(nv - 2) + vertex(nv - 1))) : vertex(nv - 1);
  const Eigen::Vector2d reference = testing::elastica_tip(kAlpha, 1.0);
  return std::hypot(tip[0] - reference[0], -tip[1] - reference[1]);
}

// log2 of successive error ratios at n = 10, 20, 40, 80.
std::vector<double> observed_rates(bool staggered, const char* label) {
  std::vector<double> errors, rates;
  for (int n : {10, 20, 40, 80}) errors.push_back(tip_error(n, staggered));
  for (std::size_t i = 1; i < errors.size(); ++i) rates.push_back(std::log2(errors[i - 1] / errors[i]));
  std::printf("%s: tip errors / L at n = 10, 20, 40, 80: %.3e %.3e %.3e %.3e (rates %.2f %.2f %.2f)\n", label,
              errors[0], errors[1], errors[2], errors[3], rates[0], rates[1], rates[2]);
  return rates;
}

TEST(RodElasticaScene, EndsAtEdgeMidpointsConvergeAtSecondOrder) {
  for (double rate : observed_rates(true, "\"ends\": \"edge_midpoints\"")) EXPECT_GE(rate, 1.9);
}

TEST(RodElasticaScene, EndsAtVerticesConvergeAtFirstOrder) {
  for (double rate : observed_rates(false, "\"ends\": \"vertices\" (default)")) {
    EXPECT_GT(rate, 0.8);
    EXPECT_LT(rate, 1.2);
  }
}

TEST(RodElasticaScene, EndPlacementIsParsedAndChecked) {
  // The staggered line: the first and last edges' midpoints are `from` and `to`.
  const RodSceneSpec spec = parse_rod_scene(cantilever_scene(4, true));
  const Eigen::MatrixX3d& x = spec.rods[0].points;
  ASSERT_EQ(x.rows(), 6);
  EXPECT_NEAR(x(0, 0), -0.125, 1e-15);
  EXPECT_NEAR(0.5 * (x(0, 0) + x(1, 0)), 0.0, 1e-15);
  EXPECT_NEAR(0.5 * (x(4, 0) + x(5, 0)), 1.0, 1e-15);
  // The end load is split over the last edge.
  ASSERT_EQ(spec.rods[0].point_loads.size(), 2u);
  EXPECT_EQ(spec.rods[0].point_loads[0].vertex, 4);
  EXPECT_EQ(spec.rods[0].point_loads[1].vertex, 5);
  EXPECT_EQ(spec.rods[0].point_loads[0].force[1], -0.5 * kAlpha);
  // Bad values and combinations name their key.
  auto refused = [](nlohmann::json scene, const std::string& expected) {
    try {
      parse_rod_scene(scene, "ends.json");
      ADD_FAILURE() << "accepted: " << scene.dump();
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  nlohmann::json bad = cantilever_scene(4, true);
  bad["rods"][0]["ends"] = "midpoints";
  refused(bad, "rods[0].ends");
  bad = cantilever_scene(4, true);
  bad["rods"][0]["point_loads"][0]["vertex"] = 3;
  refused(bad, "exactly one of 'vertex' and 'end'");
  bad = cantilever_scene(4, true);
  bad["rods"][0]["point_loads"][0]["end"] = "tip";
  refused(bad, "rods[0].point_loads[0].end");
  bad = {{"rods",
          {{{"circle", {{"radius", 1.0}, {"vertices", 8}}},
            {"ends", "edge_midpoints"},
            {"cross_section", {{"radius", 0.01}}},
            {"material", {{"youngs_modulus", 1e6}}}}}}};
  refused(bad, "rods[0].ends: a closed rod has no ends");
}

}  // namespace
}  // namespace tailor::rod_elastica_scene_test
