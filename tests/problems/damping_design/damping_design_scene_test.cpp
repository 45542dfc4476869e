// The "damping_design" scene section: parsing with key-path errors for bad input, and a short
// `tailor run` of a coarse plate that writes report.json and the plots.
#include "problems/damping_design/damping_design_scene.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "../../support/report_checks.hpp"
#include "../../support/temp_folder.hpp"
#include "problems/fem/scene.hpp"
#include "problems/scene_kinds.hpp"
#include "problems/scene_node.hpp"

namespace tailor::damping_design_scene_test {
namespace {

const char* kCoarse = R"({"name": "coarse", "damping_design": {
  "plate": {"cells": [8, 2, 1]}, "rayleigh": {"alpha": 0.4, "beta": 5e-4},
  "examples": [{"mode": 0, "scale": 0.1}, {"mode": 1, "scale": 3.0}],
  "time_step": 0.004, "steps": 300,
  "curve": {"knots": [0.0, 0.01, 0.02, 0.04], "values": [0.3, 1.0, 3.0, 5.0], "steps": 200}}})";

// The scene's text as `tailor` parses it.
DampingStudyOptions parse_damping_design(const std::string& text, const std::string& source) {
  return tailor::parse_damping_design(scene_from_text(text, source).node());
}

TEST(DampingDesignScene, ParsesAndReportsBadKeys) {
  const DampingStudyOptions o = parse_damping_design(kCoarse, "coarse.json");
  EXPECT_EQ(o.plate.cells_length, 8);
  ASSERT_EQ(o.plate.controls.size(), 2u);
  EXPECT_EQ(o.plate.controls[1][0], 3.0);
  EXPECT_EQ(o.curve.knots.size(), 4);
  EXPECT_EQ(o.plate.measured_modes, 3);
  const std::string bad_scale =
      std::string(kCoarse).replace(std::string(kCoarse).find("\"scale\": 3.0"), 12, "\"scale\": -3");
  try {
    parse_damping_design(bad_scale, "bad.json");
    FAIL() << "a negative scale was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("examples[1].scale"), std::string::npos) << e.what();
  }
  const std::string unknown =
      std::string(kCoarse).replace(std::string(kCoarse).find("\"steps\": 300"), 12, "\"stepz\": 300");
  try {
    parse_damping_design(unknown, "bad.json");
    FAIL() << "a misspelled key was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.json: damping_design.stepz: unknown key"), std::string::npos)
        << e.what();
  }
}

TEST(DampingDesignScene, RunWritesReportAndPlots) {
  testing::TempFolder folder("damping_design_scene");
  const std::string scene = folder / "coarse.json";
  std::string text = kCoarse;
  text.replace(text.find("\"steps\": 300"), 12, "\"steps\": 60");
  text.replace(text.find("\"steps\": 200"), 12, "\"steps\": 60");
  std::ofstream(scene) << text;
  const SceneFile file = read_scene_file(scene);
  ASSERT_EQ(recognise_scene_kind(file.document).name, "damping_design");
  std::ostringstream log;
  run_damping_design_scene(file.node(), folder / "out",
                           &log);  // too short to judge the rates (see damping_study_test)
  EXPECT_NE(log.str().find("mode 2"), std::string::npos) << log.str();
  for (const char* name : {"report.json", "envelope.png", "gamma_curve.png", "cycle_loss.png"})
    EXPECT_TRUE(std::filesystem::exists(folder / ("out/" + std::string(name)))) << name;
  testing::expect_report_header(folder / "out/report.json");
}

}  // namespace
}  // namespace tailor::damping_design_scene_test
