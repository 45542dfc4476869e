// The periodic-cell scene with a "rod_network" section (problems/homogenization/
// rod_network_scene.hpp) and `tailor homogenize` on it: parsing, errors naming file and key,
// outputs. The numbers are validated in tests/forward/homogenization/rod_network_cell_test.cpp.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../../support/report_checks.hpp"
#include "../../support/temp_folder.hpp"
#include "problems/fem/scene.hpp"
#include "problems/homogenization/homogenize_command.hpp"
#include "problems/json_text.hpp"
#include "problems/scene_kinds.hpp"
#include "problems/scene_node.hpp"

namespace tailor::rod_network_scene_test {
namespace {

const char* const kSquare = R"({
  "type": "periodic_cell",
  "rod_network": {"pattern": "square", "bar_length": 2, "radius": 0.05, "youngs_modulus": 3,
                  "poisson_ratio": 0.3, "edges_per_bar": 4, "depth": 0.1},
  "directions": 8
})";

const char* const kExplicit = R"({
  "type": "periodic_cell",
  "rod_network": {"lattice": [[2, 0], [0, 2]], "joints": [[0, 0]],
                  "bars": [{"from": 0, "to": 0, "shift": [1, 0]}, {"from": 0, "to": 0, "shift": [0, 1]}],
                  "radius": 0.05, "youngs_modulus": 3, "shear_modulus": 1.1538461538461537, "edges_per_bar": 4}
})";

CellScene read(const testing::TempFolder& folder, const std::string& name, const std::string& text) {
  const std::string path = folder / name;
  std::ofstream(path) << text;
  const SceneFile file = read_scene_file(path);
  CellScene scene = parse_cell_scene(file.node(), file.directory());
  scene.name = file.name();
  return scene;
}

TEST(RodNetworkScene, PatternAndExplicitFormsGiveTheSameCellAndTheOutputs) {
  const testing::TempFolder folder("rod_network_scene");
  const CellScene pattern = read(folder, "square.json", kSquare);
  const CellScene explicit_form = read(folder, "explicit.json", kExplicit);
  ASSERT_TRUE(pattern.rod_network && explicit_form.rod_network);
  EXPECT_EQ(pattern.rod_network->depth, 0.1);
  const std::string out = folder / "out";
  const HomogenizeRun run = homogenize_scene(pattern, out, nullptr);
  const HomogenizeRun same = homogenize_scene(explicit_form, folder / "out2", nullptr);
  EXPECT_LT((run.result.stiffness - same.result.stiffness).norm(), 1e-12 * run.result.stiffness.norm());
  // Along the bars: E pi a^2 / l (membrane), / depth in "stiffness".
  EXPECT_NEAR(run.result.stiffness(0, 0), 3.0 * M_PI * 0.05 * 0.05 / 2.0, 1e-12);
  std::ifstream in(out + "/report.json");
  const nlohmann::json report = parse_json(in);
  EXPECT_EQ(report["mode"], "rod_network");
  EXPECT_NEAR(report["stiffness"][0][0].get<double>(), 3.0 * M_PI * 0.05 * 0.05 / 2.0 / 0.1, 1e-12);
  EXPECT_EQ(report["directional"][0]["membrane_youngs_modulus"].size(), 9u);
  testing::expect_report_header(out + "/report.json");
  for (const char* file : {"youngs_modulus_polar.png", "poisson_ratio.png", "load_case_11.vtu",
                           "load_case_22.vtu", "load_case_12.vtu"})
    EXPECT_TRUE(std::filesystem::exists(out + "/" + file)) << file;
}

TEST(RodNetworkScene, ErrorsNameTheFileAndKey) {
  const testing::TempFolder folder("rod_network_scene_errors");
  const auto expect_error = [&](std::string text, const std::string& from, const std::string& to,
                                const std::string& fragment) {
    text.replace(text.find(from), from.size(), to);
    try {
      read(folder, "bad.json", text);
      ADD_FAILURE() << "accepted: " << fragment;
    } catch (const SceneError& e) {
      EXPECT_THAT(e.what(), ::testing::HasSubstr(fragment));
      EXPECT_THAT(e.what(), ::testing::HasSubstr("bad.json"));
    }
  };
  expect_error(kSquare, "\"radius\"", "\"radus\"", "rod_network.radus: unknown key");
  expect_error(kExplicit, "\"to\": 0, \"shift\": [0, 1]", "\"to\": 2, \"shift\": [0, 1]",
               "rod_network.bars[1].to: no such joint");
  expect_error(kExplicit, "[0, 1]}]", "[0, 0]}]", "rod_network: RodNetwork: bar 1 has zero length");
  expect_error(kSquare, "\"pattern\": \"square\"", "\"pattern\": \"kagome\"", "rod_network.pattern");
  expect_error(kSquare, "\"directions\": 8", "\"directions\": 8, \"plane\": \"stress\"",
               "plane: does not apply to a \"rod_network\" cell");
  expect_error(kExplicit, "\"shear_modulus\"", "\"poisson_ratio\": 0.3, \"shear_modulus\"",
               "give exactly one of \"shear_modulus\" and \"poisson_ratio\"");
}

}  // namespace
}  // namespace tailor::rod_network_scene_test
