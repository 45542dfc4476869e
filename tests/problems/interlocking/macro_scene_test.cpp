// The "interlocking_macro" scene kind: a small drape's outputs, and the refusal of unknown keys and
// bad boundaries with file and key path.
#include "problems/interlocking/macro_scene.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "problems/scene_error.hpp"
#include "problems/scene_kinds.hpp"
#include "tests/support/test_paths.hpp"

namespace tailor::interlocking_macro_scene_test {
namespace {

// A boundary with the square net's stretch and compression limits along the axes and the
// diagonals (8 principal rays), a 6 x 6 sheet.
const char* kScene = R"({
  "name": "small_drape",
  "interlocking_macro": {
    "boundary": {"order": 2, "limit_strains": [[0.066, 0], [0.066, 0.066], [0, 0.066], [-0.2, 0.066],
                                               [-0.2, 0], [-0.14, -0.14], [0, -0.2], [0.066, -0.2]]},
    "material": {"stiffness": 1.0, "barrier_stiffness": 1.0, "barrier_activation": 0.1, "bending_stiffness": 0.001},
    "drape": {"width": 1.2, "divisions": 6, "sphere_radius": 1.0, "contact_activation": 0.01}
  }
})";

TEST(InterlockingMacroScene, DrapeWritesItsOutputs) {
  const SceneFile file = scene_from_text(kScene, "small.json");
  InterlockingMacroScene scene = parse_interlocking_macro_scene(file.node());
  scene.name = "small_drape";
  const std::string out =
      (std::filesystem::temp_directory_path() / "tailor_interlocking_macro_scene_test").string();
  std::filesystem::remove_all(out);
  ASSERT_TRUE(run_interlocking_macro(scene, out, nullptr));
  for (const char* f : {"report.json", "sheet.vtu", "sphere.vtu", "boundary_fit.png"})
    EXPECT_TRUE(std::filesystem::exists(out + "/" + f)) << f;
  std::ifstream in(out + "/report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_EQ(report["status"].get<std::string>(), "converged");
  EXPECT_GT(report["drape"]["min_margin"].get<double>(), 0.0);
  EXPECT_GT(report["drape"]["contact_vertices"].get<int>(), 0);
  EXPECT_EQ(report["fit"]["samples"].get<int>(), 8);
}

TEST(InterlockingMacroScene, UnknownKeysAndBadBoundariesAreRefusedWithTheirPath) {
  std::string text = kScene;
  text.replace(text.find("\"sphere_radius\""), 15, "\"sphere_radios\"");
  try {
    parse_interlocking_macro_scene(scene_from_text(text, "bad.json").node());
    FAIL() << "accepted an unknown key";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("interlocking_macro.drape.sphere_radios"), std::string::npos)
        << e.what();
  }
  std::string high = kScene;
  high.replace(high.find("\"order\": 2"), 10, "\"order\": 9");  // 5 distinct directions cannot fix order 9
  EXPECT_THROW(parse_interlocking_macro_scene(scene_from_text(high, "order.json").node()), SceneError);
  std::string odd = kScene;
  odd.replace(odd.find("\"divisions\": 6"), 14, "\"divisions\": 5");
  EXPECT_THROW(parse_interlocking_macro_scene(scene_from_text(odd, "odd.json").node()), SceneError);
}

// The shipped scene is recognised as this kind and parses; its 32 native limits fit at order 12
// within 2 10^-3 (the docs' figures: rms 8.0 10^-4, largest 1.7 10^-3).
TEST(InterlockingMacroScene, ShippedSceneParsesAndFits) {
  const SceneFile file =
      read_scene_file(std::string(::tailor::testing::source_dir()) + "/scenes/interlocking_macro_drape.json");
  EXPECT_EQ(recognise_scene_kind(file.document).name, "macro_sheet");
  const InterlockingMacroScene scene = parse_interlocking_macro_scene(file.node());
  ASSERT_EQ(scene.limit_strains.size(), 32U);
  const interlocking::BoundaryFit fit = interlocking::fit_boundary(scene.limit_strains, scene.order);
  EXPECT_LT(fit.max_residual, 2e-3);
}

}  // namespace
}  // namespace tailor::interlocking_macro_scene_test
