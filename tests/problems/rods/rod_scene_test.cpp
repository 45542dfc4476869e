// The "rods" scene section: parsing with clear errors, a cantilever solved and written as .vtu
// polylines. Reference for the small-load deflection: Euler-Bernoulli, P L^3 / (3 EI).
#include "problems/rods/rod_scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "../../support/temp_folder.hpp"
#include "problems/fem/scene.hpp"
#include "problems/json_text.hpp"
#include "tests/support/test_paths.hpp"

namespace tailor::rod_scene_test {
namespace {

nlohmann::json cantilever_scene(double tip_load) {
  const double r = 1e-2, E = 4.0 / (M_PI * std::pow(r, 4));  // EI = 1
  return parse_json(R"({
    "rods": [{
      "name": "beam",
      "line": {"from": [0, 0, 0], "to": [1, 0, 0], "vertices": 41},
      "cross_section": {"shape": "circle", "radius": )" +
                    std::to_string(r) + R"(},
      "material": {"youngs_modulus": )" +
                    std::to_string(E) + R"(},
      "clamp": ["first"],
      "point_loads": [{"vertex": 40, "force": [0, )" +
                    std::to_string(-tip_load) + R"(, 0]}]
    }],
    "load_steps": 2
  })");
}

TEST(RodScene, CantileverSmallLoadMatchesEulerBernoulliAndWritesVtu) {
  const double P = 1e-3;
  const RodSceneSpec spec = parse_rod_scene(cantilever_scene(P));
  const auto dir = testing::unique_temp_path("tailor_rod_scene_test");
  const RodSimulation sim = simulate_rods(spec, dir.string());
  ASSERT_TRUE(sim.converged);
  // Tip vertex 40: deflection vs P L^3 / 3EI (first order in h with the clamp at a vertex).
  const double deflection = -sim.state[3 * 40 + 1];
  EXPECT_NEAR(deflection / (P / 3.0), 1.0, 0.05);
  std::ifstream vtu(sim.vtu_path);
  std::stringstream text;
  text << vtu.rdbuf();
  for (const char* field : {"\"m1\"", "\"m2\"", "\"theta\"", "\"axial_strain\"", "\"kappa\"", "\"twist\""})
    EXPECT_NE(text.str().find(field), std::string::npos) << field;
  std::filesystem::remove_all(dir);
}

TEST(RodScene, BadInputNamesTheKey) {
  nlohmann::json scene = cantilever_scene(1.0);
  scene["rods"][0]["cross_section"].erase("radius");
  try {
    parse_rod_scene(scene);
    FAIL() << "expected an exception";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("rods[0].cross_section"), std::string::npos) << e.what();
  }
  scene = cantilever_scene(1.0);
  scene["rods"][0]["clamp"] = {"middle"};
  EXPECT_THROW(parse_rod_scene(scene), SceneError);
  scene = cantilever_scene(1.0);
  scene["rods"][0]["cross_section"]["shape"] = "hexagon";
  EXPECT_THROW(parse_rod_scene(scene), SceneError);
}

// A misspelled key is refused at every level, with the scene file and the key path, instead of
// leaving a default in place (before, "youngs_modulu" or "forse" changed nothing and said nothing).
TEST(RodScene, UnknownKeysAreRefusedWithFileAndKeyPath) {
  const auto expect_refused = [](const nlohmann::json& scene, const std::string& fragment) {
    try {
      parse_rod_scene(scene, "bent.json");
      ADD_FAILURE() << "accepted: " << fragment;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("bent.json: " + fragment), std::string::npos) << e.what();
    }
  };
  nlohmann::json scene = cantilever_scene(1.0);
  scene["rods"][0]["clamps"] = {"first"};
  expect_refused(scene, "rods[0].clamps: unknown key (expected one of name, points, line");
  scene = cantilever_scene(1.0);
  scene["rods"][0]["material"]["youngs_modulu"] = 1.0;
  expect_refused(scene, "rods[0].material.youngs_modulu: unknown key");
  scene = cantilever_scene(1.0);
  scene["rods"][0]["cross_section"]["radiu"] = 1.0;
  expect_refused(scene, "rods[0].cross_section.radiu: unknown key");
  scene = cantilever_scene(1.0);
  scene["rods"][0]["line"]["vertex"] = 3;
  expect_refused(scene, "rods[0].line.vertex: unknown key");
  scene = cantilever_scene(1.0);
  scene["rods"][0]["point_loads"][0]["forse"] = {0, 1, 0};
  expect_refused(scene, "rods[0].point_loads.forse: unknown key");
  scene = cantilever_scene(1.0);
  scene["rods"][0]["twisting_moments"] = {{{"edge", 3}, {"moment", 1.0}, {"axis", 2}}};
  expect_refused(scene, "rods[0].twisting_moments.axis: unknown key");
  // Errors that were already refused now name the file too.
  scene = cantilever_scene(1.0);
  scene["rods"][0]["clamp"] = {"middle"};
  expect_refused(scene, "rods[0].clamp: expected");
  // The shipped scenes use only documented keys.
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(::tailor::testing::source_dir()) + "/scenes/rods")) {
    if (entry.path().extension() != ".json") continue;
    std::ifstream in(entry.path());
    const nlohmann::json document = parse_json(in);
    if (document.contains("mesh")) continue;  // rods with a mesh: checked by their own tests
    EXPECT_NO_THROW(parse_rod_scene(document, entry.path().string())) << entry.path();
  }
}

}  // namespace
}  // namespace tailor::rod_scene_test
