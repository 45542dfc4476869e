// `tailor modes`: report.json and modes.vtu of a scene's modal analysis.
#include "problems/fem/modes_command.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "../support/report_checks.hpp"
#include "../support/temp_folder.hpp"
#include "problems/json_text.hpp"
#include "scene_text.hpp"

namespace tailor::modes_command_test {
namespace {

using namespace tailor::testing;

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  return parse_json(in);
}

const std::string kDensity = R"("poisson_ratio": 0.3, "density": 2)";

TEST(ModesCommand, WritesFrequenciesAndModeShapes) {
  TempFolder folder("modes_supported");
  // The box's statically determinate supports remove the rigid motions and nothing more.
  const Scene scene = parse_scene(with(R"("poisson_ratio": 0.3)", kDensity), "box.json", ".");
  const ModesRun run = modes_scene(scene, 4, folder.str());
  testing::expect_report_header(run.report_path);
  const nlohmann::json report = read_json(run.report_path);
  EXPECT_EQ(report["kind"], "modes");
  EXPECT_EQ(report["count"], 4);
  EXPECT_EQ(report["rigid_modes"], 0);
  ASSERT_EQ(report["frequencies_hz"].size(), 4u);
  for (int j = 0; j < 4; ++j)
    EXPECT_NEAR(report["frequencies_hz"][j].get<double>(), run.modes.frequencies[j], 1e-12);
  EXPECT_GT(run.modes.frequencies[0], 0.0);
  EXPECT_NEAR(report["total_mass"].get<double>(), 4.0, 1e-12);  // volume 2, density 2
  std::ifstream vtu(run.modes_path);
  const std::string text((std::istreambuf_iterator<char>(vtu)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("Name=\"mode_4\""), std::string::npos);
}

TEST(ModesCommand, FreeBodySetsItsSixRigidModesApart) {
  TempFolder folder("modes_free");
  std::string text = with(R"("poisson_ratio": 0.3)", kDensity);
  const auto begin = text.find("\"dirichlet\"");
  const auto end = text.find("\"loads\"");
  text.erase(begin, end - begin);
  const ModesRun run = modes_scene(parse_scene(text, "free.json", "."), 3, folder.str());
  const nlohmann::json report = read_json(run.report_path);
  EXPECT_EQ(report["rigid_modes"], 6);
  EXPECT_EQ(report["rigid_eigenvalues"].size(), 6u);
  EXPECT_GT(run.modes.eigenvalues[0], 1e6 * run.modes.rigid_eigenvalues.cwiseAbs().maxCoeff());
}

TEST(ModesCommand, NeedsDensityAndASensibleCount) {
  TempFolder folder("modes_bad");
  EXPECT_THROW(modes_scene(parse_scene(small_box_scene(), "box.json", "."), 3, folder.str()), SceneError);
  const Scene scene = parse_scene(with(R"("poisson_ratio": 0.3)", kDensity), "box.json", ".");
  EXPECT_THROW(modes_scene(scene, 0, folder.str()), SceneError);
  EXPECT_THROW(modes_scene(scene, 100000, folder.str()), SceneError);
}

}  // namespace
}  // namespace tailor::modes_command_test
