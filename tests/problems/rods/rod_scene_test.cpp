// The "rods" scene section: parsing with clear errors, a cantilever solved and written as .vtu
// polylines. Reference for the small-load deflection: Euler-Bernoulli, P L^3 / (3 EI).
#include "problems/rods/rod_scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "../../support/temp_folder.hpp"
#include "problems/fem/scene.hpp"
#include "problems/json_text.hpp"
#include "problems/rods/rod_inverse.hpp"
#include "problems/scene_kinds.hpp"
#include "problems/scene_node.hpp"
#include "rod_scene_files.hpp"
#include "tests/support/test_paths.hpp"

namespace tailor::rod_scene_test {
namespace {

using testing::read_rod_scene;

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

// The error of parsing `scene` as the file "bent.json" (empty when it parses).
std::string bent_error(const nlohmann::json& scene) {
  try {
    parse_rod_scene(scene, "bent.json");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

void expect_refused(const nlohmann::json& scene, const std::string& fragment) {
  const std::string error = bent_error(scene);
  EXPECT_NE(error.find("bent.json: " + fragment), std::string::npos) << fragment << "\n"
                                                                     << (error.empty() ? "accepted" : error);
}

// A misspelled key is refused at every level with the scene file and its full key path, instead
// of leaving a default in place (before, "youngs_modulu" or "forse" changed nothing and said nothing).
TEST(RodScene, MisspelledKeysAreRefusedWithFileAndKeyPath) {
  const nlohmann::json cantilever = cantilever_scene(1.0);
  nlohmann::json s = cantilever;
  s["gravitty"] = {0, -9.81, 0};
  expect_refused(s, "gravitty: unknown key (allowed here: name, description, rods, joints, gravity, ");
  s = cantilever;
  s["rods"][0]["clamps"] = {"first"};
  expect_refused(s, "rods[0].clamps: unknown key (allowed here: name, points, line, circle, closed, ");
  s = cantilever;
  s["rods"][0]["material"]["youngs_modulu"] = 1.0;
  expect_refused(s,
                 "rods[0].material.youngs_modulu: unknown key (allowed here: youngs_modulus, shear_modulus, "
                 "density)");
  s = cantilever;
  s["rods"][0]["cross_section"]["radiu"] = 1.0;
  expect_refused(s, "rods[0].cross_section.radiu: unknown key (allowed here: shape, radius, aspect)");
  s = cantilever;
  s["rods"][0]["line"]["vertex"] = 3;
  expect_refused(s, "rods[0].line.vertex: unknown key (allowed here: from, to, vertices)");
  s = cantilever;
  s["rods"][0]["point_loads"].push_back({{"vertex", 3}, {"forse", {0, 1, 0}}});
  expect_refused(s, "rods[0].point_loads[1].forse: unknown key (allowed here: vertex, end, force)");
  s = cantilever;
  s["rods"][0]["twisting_moments"] = {{{"edge", 3}, {"moment", 1.0}, {"axis", 2}}};
  expect_refused(s, "rods[0].twisting_moments[0].axis: unknown key (allowed here: edge, moment)");
  s = cantilever;
  s["rods"][0]["clamp"] = {"first", "lats"};
  expect_refused(s, "rods[0].clamp[1]: expected one of first, last, got \"lats\"");
  s = read_rod_scene("rod_ring.json");
  s["rods"][0]["circle"]["centre"] = {0, 0, 0};
  expect_refused(s, "rods[0].circle.centre: unknown key (allowed here: center, radius, normal, ");
  s = read_rod_scene("rod_frame.json");
  s["joints"][0]["kind"] = "rigid";
  expect_refused(s, "joints[0].kind: unknown key (allowed here: type, rods)");
  s = read_rod_scene("rod_frame.json");
  s["joints"][0]["rods"][1]["vertx"] = 0;
  expect_refused(s, "joints[0].rods[1].vertx: unknown key (allowed here: rod, vertex)");
  s = read_rod_scene("rod_swing.json");
  s["dynamics"]["time_stp"] = 0.1;
  expect_refused(s, "dynamics.time_stp: unknown key (allowed here: scheme, time_step, ");
}

// Wrong types, values out of range and contradictory keys: each error names its full path.
TEST(RodScene, BadValuesNameTheirPath) {
  const nlohmann::json cantilever = cantilever_scene(1.0);
  nlohmann::json s = cantilever;
  s["rods"][0]["material"]["youngs_modulus"] = "1e9";
  expect_refused(s, "rods[0].material.youngs_modulus: expected a number > 0, got a string \"1e9\"");
  s = cantilever;
  s["rods"][0]["pin"] = {3, "7"};
  expect_refused(s, "rods[0].pin[1]: expected a number, got a string \"7\"");
  s = cantilever;
  s["rods"][0]["pin"] = {41};
  expect_refused(s, "rods[0].pin[0]: expected an integer in [0, 40], got 41");
  s = cantilever;
  s["gravity"] = {0, "down", 0};
  expect_refused(s, "gravity[1]: expected a number, got a string \"down\"");
  s = cantilever;
  s["rods"][0]["point_loads"][0]["force"] = {0, 1};
  expect_refused(s, "rods[0].point_loads[0].force: expected an array of 3 numbers, got an array of 2");
  s = cantilever;
  s["rods"][0]["material"] = 7;
  expect_refused(s, "rods[0].material: expected an object, got 7");
  s = cantilever;
  s["rods"][0]["points"] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  expect_refused(s, "rods[0]: give only one of 'points', 'line' and 'circle'");
  s = read_rod_scene("rod_frame.json");
  s["joints"][0]["rods"] = {{"rod", 0}};
  expect_refused(s, "joints[0].rods: expected an array, got an object");
  s = read_rod_scene("rod_swing.json");
  s["dynamics"]["rayleigh"] = {{"alpha", 0.0}};
  expect_refused(s, "dynamics.rayleigh: Rayleigh damping is not implemented for rod scenes");
  expect_refused(nlohmann::json::array(), "(top level): expected an object, got an array of 0");
}

// Read from a file, every kind of rod scene names that file: the plain, the FEM and the design scene.
TEST(RodScene, SceneFileErrorsNameTheFile) {
  const testing::TempFolder folder("rod_scene_file_errors");
  const auto write = [&](const std::string& name, nlohmann::json scene) {
    const std::string path = folder / name;
    std::ofstream(path) << scene.dump();
    return path;
  };
  // The error of `run` starts with `expected`.
  const auto expect_error = [](const std::function<void()>& run, const std::string& expected) {
    std::string error;
    try {
      run();
    } catch (const SceneError& e) {
      error = e.what();
    }
    EXPECT_EQ(error.substr(0, expected.size()), expected) << error;
  };
  std::ostringstream log;
  const auto simulate = [&](const std::string& path) {
    const SceneFile file = read_scene_file(path);
    simulate_rod_scene(file.node(), file.directory(), folder / "out", &log);
  };
  nlohmann::json s = cantilever_scene(1.0);
  s["rods"][0]["cross_section"]["radis"] = 0.01;
  const std::string plain = write("plain.json", s);
  expect_error([&] { simulate(plain); }, plain + ": rods[0].cross_section.radis: unknown key");
  s = read_rod_scene("rods_and_beam.json");
  s["solvr"] = nlohmann::json::object();
  const std::string fem = write("fem.json", s);
  expect_error([&] { simulate(fem); }, fem + ": solvr: unknown key");
  s = read_rod_scene("rod_stiffness_design.json");
  s["rods"][0]["material"]["shear_moduls"] = 1.0;
  const std::string design = write("design.json", s);
  expect_error([&] { build_rod_inverse(read_scene_file(design).node(), "design"); },
               design + ": rods[0].material.shear_moduls: unknown key");
}

// The shipped scenes, those with a mesh or an inverse section included, use only documented keys.
TEST(RodScene, ShippedScenesParse) {
  int parsed = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(::tailor::testing::source_dir()) + "/scenes/rods")) {
    if (entry.path().extension() != ".json") continue;
    const std::string path = entry.path().string();
    const nlohmann::json document = read_scene_document(path);
    EXPECT_NO_THROW(parse_rod_scene(SceneNode(document, path, ""))) << path;
    ++parsed;
  }
  EXPECT_EQ(parsed, 8);
}

}  // namespace
}  // namespace tailor::rod_scene_test
