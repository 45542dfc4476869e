// Material-fit scenes: the shipped scenes parse, other scenes are not taken for material fits,
// and bad input is reported with the file and key path.
#include "problems/material_fit/material_fit_scene.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "problems/fem/scene.hpp"
#include "problems/scene_kinds.hpp"
#include "problems/scene_node.hpp"
#include "tests/support/report_checks.hpp"
#include "tests/support/temp_folder.hpp"
#include "tests/support/test_paths.hpp"

namespace tailor::material_fit_scene_test {
namespace {

const std::string kScenes = testing::kScenesDir + "/";

TEST(MaterialFitScene, ShippedScenesParse) {
  for (const char* name :
       {"spline_fit_neo_hookean", "spline_fit_stable_neo_hookean", "spline_design_locking"}) {
    const SceneFile file = read_scene_file(kScenes + "material_fit/" + name + ".json");
    ASSERT_EQ(recognise_scene_kind(file.document).name, "material_fit") << file.path;
    const MaterialFitSpec spec = parse_material_fit_scene(file.node());
    EXPECT_EQ(file.name(), name);
    EXPECT_EQ(spec.source, file.path);
    EXPECT_FALSE(spec.cases.empty());
  }
  EXPECT_NE(recognise_scene_kind(read_scene_file(kScenes + "cantilever.json").document).name, "material_fit");
}

// The scene's text as `tailor` parses it.
MaterialFitSpec parse_material_fit(const std::string& text, const std::string& source) {
  return parse_material_fit_scene(scene_from_text(text, source).node());
}

std::string scene_with(const std::string& replace, const std::string& with) {
  std::string text = R"({
    "type": "material_fit",
    "curves": {"uniaxial": {"lower": 0.5, "upper": 2.0, "intervals": 4},
               "biaxial": {"lower": 0.25, "upper": 4.0, "intervals": 4},
               "volumetric": {"lower": 0.1, "upper": 3.0, "intervals": 4}},
    "load_cases": [{"name": "pull", "kind": "uniaxial", "amplitudes": [1.1, 1.2], "forces": [0.1, 0.2]}],
    "initial": {"preset": "corotated", "youngs_modulus": 1.0, "poisson_ratio": 0.3}
  })";
  if (!replace.empty()) {
    const auto at = text.find(replace);
    EXPECT_NE(at, std::string::npos) << replace;
    text.replace(at, replace.size(), with);
  }
  return text;
}

void expect_error(const std::string& text, const std::string& fragment) {
  try {
    parse_material_fit(text, "fit.json");
    ADD_FAILURE() << "no error for " << fragment;
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(MaterialFitScene, ReportsBadInputWithItsKeyPath) {
  EXPECT_NO_THROW(parse_material_fit(scene_with("", ""), "fit.json"));
  expect_error(scene_with("\"lower\": 0.5, \"upper\": 2.0", "\"lower\": 2.5, \"upper\": 2.0"),
               "curves.uniaxial");
  expect_error(scene_with("\"forces\": [0.1, 0.2]", "\"forces\": [0.1]"), "load_cases[0].forces");
  expect_error(scene_with("\"amplitudes\": [1.1, 1.2]", "\"amplitudes\": [1.1, -1.2]"),
               "stretches must be > 0");
  expect_error(scene_with("\"kind\": \"uniaxial\"", "\"kind\": \"torsion\""), "load_cases[0].kind");
  expect_error(scene_with(", \"forces\": [0.1, 0.2]", ""), "needs \"forces\"");
  expect_error(scene_with("\"preset\": \"corotated\"", "\"preset\": \"mooney\""), "initial.preset");
  expect_error(
      scene_with("\"type\": \"material_fit\",", "\"type\": \"material_fit\", \"convex\": [\"uniaxial\"],"),
      "constrained optimizer");
  const std::string slsqp = "\"type\": \"material_fit\", \"optimizer\": {\"backend\": \"nlopt_slsqp\"}, ";
  expect_error(scene_with("\"type\": \"material_fit\",",
                          slsqp + "\"shape\": [{\"curve\": \"volumetric\", \"kind\": \"flat\"}],"),
               "fit.json: shape[0].kind: expected one of");
  expect_error(
      scene_with("\"type\": \"material_fit\",", slsqp + "\"shape\": [{\"curve\": \"volumetric\", \"kind\": "
                                                        "\"decreasing\", \"range\": [1, 0.5]}],"),
      "fit.json: shape[0].range: expected [lower, upper] with lower < upper");
  const MaterialFitSpec shaped = parse_material_fit(
      scene_with("\"type\": \"material_fit\",",
                 slsqp + "\"convex\": [\"uniaxial\"], \"shape\": [{\"curve\": \"volumetric\", \"kind\": "
                         "\"decreasing\", \"range\": [0.1, 1]}],"),
      "fit.json");
  ASSERT_EQ(shaped.shapes.size(), 2u);
  EXPECT_EQ(shaped.shapes[1].shape, CurveShape::decreasing);
  EXPECT_EQ(shaped.shapes[1].upper, 1.0);
  expect_error(scene_with("\"type\": \"material_fit\",", "\"type\": \"material_fit\", \"colour\": 1,"),
               "colour");
  expect_error("{", "invalid JSON");
}

}  // namespace
}  // namespace tailor::material_fit_scene_test

namespace tailor::material_fit_scene_test {
namespace {

// `tailor run` dispatches a material-fit scene and writes the report and one plot per case.
TEST(MaterialFitCli, RunWritesReportAndPlots) {
  testing::TempFolder folder("material_fit_cli");
  {
    std::ofstream scene(folder / "fit.json");
    scene << scene_with("\"initial\"", "\"name\": \"tiny\", \"initial\"");
  }
  const std::string command = std::string(::tailor::testing::binary_dir()) + "/bin/tailor run " +
                              (folder / "fit.json") + " --out " + (folder / "out") + " --quiet > " +
                              (folder / "log") + " 2>&1";
  const int status = std::system(command.c_str());
  std::ifstream log(folder / "log");
  const std::string output((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << output;
  EXPECT_NE(output.find("material fit 'tiny'"), std::string::npos) << output;
  testing::expect_report_header(folder / "out/report.json");
  EXPECT_TRUE(std::filesystem::exists(folder / "out/force_pull.png")) << output;
}

}  // namespace
}  // namespace tailor::material_fit_scene_test
