// Inputs that once crashed a scene parser or made it allocate without bound, each refused now
// with a SceneError naming file and key (docs/testing.md lists how each was found). The scene
// fuzzers (fuzz/) run these parsers on mutated inputs; what they find lands here.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "../support/temp_folder.hpp"
#include "problems/fem/scene.hpp"
#include "problems/homogenization/cell_scene.hpp"
#include "problems/json_text.hpp"
#include "problems/rods/rod_scene.hpp"
#include "problems/scene_kinds.hpp"
#include "scene_text.hpp"

namespace tailor::parser_regression_test {
namespace {

using tailor::testing::TempFolder;
using tailor::testing::with;

// The SceneError message of parse_scene(json), "" when it parses; any other exception fails.
std::string scene_error(const std::string& json, const std::string& directory = "") {
  try {
    parse_scene(json, "test.json", directory);
    return "";
  } catch (const SceneError& e) {
    return e.what();
  }
}

// A data file whose first line holds 100001 numbers, followed by 100000 one-number lines. A
// reader that sizes its matrix by the first line's columns before checking them asks for
// 100001 x 100000 doubles (80 GB): std::bad_alloc (or a sanitizer's out-of-memory report).
std::string wide_then_long(const TempFolder& folder) {
  const std::string path = folder / "wide.txt";
  std::ofstream out(path);
  for (int k = 0; k <= 100000; ++k) out << "0 ";
  out << "\n";
  for (int k = 0; k < 100000; ++k) out << "0\n";
  return path;
}

TEST(ParserRegression, NodalForceFileWithAWideFirstLine) {
  TempFolder folder("regression_nodal");
  const std::string path = wide_then_long(folder);
  const std::string error =
      scene_error(with(R"("tractions")", R"("nodal_file": ")" + path + R"(", "tractions")"));
  EXPECT_NE(
      error.find("loads.nodal_file: '" + path +
                 "' line 1: expected 'vertex fx fy' or 'vertex fx fy fz' on every line, got 100001 values"),
      std::string::npos)
      << error;
}

TEST(ParserRegression, ObservationFileWithAWideFirstLine) {
  TempFolder folder("regression_observations");
  const std::string path = wide_then_long(folder);
  const std::string inverse =
      R"(, "inverse": {"design": {"parameter": "youngs_modulus", "granularity": "per_material"},
      "objective": [{"type": "observations", "file": ")" +
      path + R"("}]}})";
  const std::string error = scene_error(with("\n}", inverse));
  EXPECT_NE(
      error.find("inverse.objective[0].file: '" + path +
                 "' line 1: expected 'vertex ux uy' or 'vertex ux uy uz' on every line, got 100001 values"),
      std::string::npos)
      << error;
}

// intervals + 3 overflowed int for intervals near INT_MAX (UndefinedBehaviorSanitizer:
// signed integer overflow).
TEST(ParserRegression, SplineCurveWithIntervalsNearIntMax) {
  const std::string curve =
      R"({"lower": 0.5, "upper": 2, "intervals": 2147483646, "controls": [0, 1, 2, 3]})";
  const std::string material = R"({"elements": "all", "model": "spline", "curves": {"uniaxial": )" + curve +
                               R"(, "biaxial": )" + curve + R"(, "volumetric": )" + curve + "}}";
  const std::string error = scene_error(with(
      R"({"elements": "all", "model": "linear", "youngs_modulus": 1000, "poisson_ratio": 0.3})", material));
  EXPECT_NE(
      error.find("test.json: materials[0].curves.uniaxial.controls: expected intervals + 3 = 2147483649 "
                 "control values, got an array of 4"),
      std::string::npos)
      << error;
}

// Periodic cells are meshed while they are read: a grid whose mesh cannot exist is refused
// first, with the key path (it used to reach the mesh generator: std::invalid_argument without
// a key, or std::bad_alloc).
TEST(ParserRegression, PeriodicCellGridsTooLargeToMesh) {
  TempFolder folder("regression_cell");
  const auto cell_error = [&](const std::string& cell) {
    const std::string path = folder / "cell.json";
    std::ofstream(path) << R"({"type": "periodic_cell", "cell": )" << cell
                        << R"(, "materials": [{"youngs_modulus": 1, "poisson_ratio": 0.3}]})";
    try {
      const SceneFile file = read_scene_file(path);
      parse_cell_scene(file.node(), file.directory());
      return std::string();
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
  };
  const std::string cube =
      cell_error(R"({"lattice": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "grid": [2000, 2000, 2000]})");
  EXPECT_NE(cube.find("cell.json: cell.grid: 4.8e+10 tets would need at least"), std::string::npos) << cube;
  EXPECT_NE(cube.find("more elements than int indices can count"), std::string::npos) << cube;
  const std::string square =
      cell_error(R"({"lattice": [[1, 0], [0, 1]], "grid": [50000, 50000], "split": "crossed"})");
  EXPECT_NE(square.find("cell.json: cell.grid: 1e+10 triangles would need at least"), std::string::npos)
      << square;
  EXPECT_EQ(cell_error(R"({"lattice": [[1, 0], [0, 1]], "grid": [4, 4]})"), "");  // small grids still work
}

// When the rods parser read nlohmann::json directly, members of the wrong JSON type threw
// nlohmann's type_error (not a SceneError), and numbers beyond int were cast to int
// (undefined behaviour; UndefinedBehaviorSanitizer: float-cast-overflow).
TEST(ParserRegression, RodScenesWithValuesOfTheWrongKind) {
  const std::string rod =
      R"({"line": {"from": [0, 0, 0], "to": [1, 0, 0], "vertices": 5}, "cross_section": {"radius": 0.01},
          "material": {"youngs_modulus": 1e9}, "clamp": ["first"]})";
  const auto rod_error = [](const std::string& text) {
    try {
      parse_rod_scene(parse_json(text));
      return std::string();
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
  };
  const auto expect_error = [&](const std::string& text, const std::string& part) {
    const std::string error = rod_error(text);
    EXPECT_NE(error.find(part), std::string::npos) << text << "\n" << error;
  };
  EXPECT_EQ(rod_error(R"({"rods": [)" + rod + "]}"), "");
  expect_error(R"({"rods": [1]})", "rods scene: rods[0]: expected an object");
  expect_error(R"({"rods": [{"line": [0, 1]}]})", "rods[0].line: expected an object");
  expect_error(R"({"rods": [{"line": {"from": [0, 0, 0], "to": [1, 0, 0], "vertices": 1e300}}]})",
               "rods[0].line.vertices: expected an integer in [3, 10000000]");
  expect_error(R"({"load_steps": 1e300, "rods": [)" + rod + "]}",
               "rods scene: load_steps: expected an integer in [1, ");
  expect_error(R"({"rods": [{"name": 7, "points": [[0, 0, 0], [1, 0, 0], [2, 0, 0]]}]})",
               "rods[0].name: expected a string");
  const std::string loaded = rod.substr(0, rod.size() - 1);
  expect_error(R"({"rods": [)" + loaded + R"(, "point_loads": [3]}]})",
               "rods[0].point_loads[0]: expected an object, got 3");
  expect_error(R"({"rods": [)" + loaded + R"(, "point_loads": [{"vertex": -1e300, "force": [0, 0, 1]}]}]})",
               "rods[0].point_loads[0].vertex: expected an integer in [0, 4]");
  expect_error(R"({"rods": [)" + loaded + R"(, "cross_section": 1}]})",
               "rods[0].cross_section: expected an object");
}

}  // namespace
}  // namespace tailor::parser_regression_test
