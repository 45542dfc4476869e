// The rig_dynamics scene kind: a small arm run in full space and reduced (outputs and report),
// key errors naming file and key path, rig input checks, and the shipped scene's parse.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "problems/rig/rig_scene.hpp"
#include "problems/scene_error.hpp"
#include "problems/scene_kinds.hpp"
#include "problems/scene_node.hpp"
#include "tests/support/temp_folder.hpp"
#include "tests/support/test_paths.hpp"

namespace tailor::rig::rig_scene_test {
namespace {

// A 4 x 1 x 1-cell arm with its rig inline (weights from the arm's own blend).
nlohmann::json small_scene(bool reduced) {
  TwoBoneArmOptions arm;
  arm.cells_along = 4;
  arm.cells_across = 1;
  const TwoBoneArm generated = two_bone_arm(arm);
  nlohmann::json weights = nlohmann::json::array();
  for (int v = 0; v < generated.body.mesh.num_vertices(); ++v) {
    const Eigen::Vector2d w = two_bone_arm_weights(generated.body.mesh.rest_positions(v, 0), arm);
    weights.push_back({w[0], w[1]});
  }
  nlohmann::json rig = {{"bones",
                         {{{"name", "upper"}, {"parent", nullptr}, {"joint", {0, 0, 0}}, {"dofs", {{{"rotation", {0, 0, 1}}}}}},
                          {{"name", "fore"}, {"parent", "upper"}, {"joint", {2, -0.25, 0}}, {"dofs", {{{"rotation", {0, 0, 1}}}}}}}},
                        {"weights", weights}};
  nlohmann::json section = {{"arm", {{"cells_along", 4}, {"cells_across", 1}}},
                            {"material", {{"model", "stvk"}, {"youngs_modulus", 1e6}}},
                            {"rig", rig},
                            {"keyframes", {{{"time", 0}, {"pose", {0, 0}}}, {{"time", 0.1}, {"pose", {0, -1}}}}},
                            {"time_step", 0.01},
                            {"duration", 0.2},
                            {"output_every", 10},
                            {"marker", {4, -0.25, 0}}};
  if (reduced)
    section["reduction"] = {{"size", 6}, {"linear_modes", 4}, {"derivative_modes", 2}, {"example_poses", {{0, 0}, {0, -1}}}};
  return {{"name", "small_arm"}, {"rig_dynamics", section}};
}

RigSceneSpec parse(const nlohmann::json& document) {
  const SceneFile file = scene_from_document(document, "arm.json");
  return parse_rig_scene(file.node(), file.directory());
}

std::string parse_error(const nlohmann::json& document) {
  try {
    parse(document);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(RigScene, RunsInFullSpaceAndReducedAndWritesItsOutputs) {
  for (bool reduced : {false, true}) {
    const testing::TempFolder out(reduced ? "rig_reduced" : "rig_full");
    const RigSceneRun run = run_rig_scene(parse(small_scene(reduced)), out.str(), nullptr);
    EXPECT_TRUE(run.completed) << run.message;
    EXPECT_EQ(run.steps, 20);
    EXPECT_GT(run.max_jiggle, 1e-4);
    for (const char* file : {"report.json", "result.pvd", "jiggle.png", "frames/frame_00000.vtu", "frames/frame_00020.vtu"})
      EXPECT_TRUE(std::filesystem::exists(out / file)) << file;
    std::ifstream in(out / "report.json");
    const nlohmann::json report = nlohmann::json::parse(in);
    EXPECT_EQ(report["kind"], "rig_dynamics");
    EXPECT_EQ(report.contains("reduction"), reduced);
    EXPECT_EQ(report["dynamics"]["steps"], 20);
  }
}

TEST(RigScene, ErrorsNameTheKeyPath) {
  nlohmann::json d = small_scene(true);
  d["rig_dynamics"]["reduction"]["sise"] = 3;
  EXPECT_NE(parse_error(d).find("arm.json: rig_dynamics.reduction.sise: unknown key"), std::string::npos) << parse_error(d);
  d = small_scene(false);
  d["rig_dynamics"]["rig"]["weights"].erase(0);
  EXPECT_NE(parse_error(d).find("rig_dynamics.rig.weights: needs one row per mesh vertex"), std::string::npos)
      << parse_error(d);
  d = small_scene(false);
  d["rig_dynamics"]["rig"]["weights"][3] = {0.7, 0.7};
  EXPECT_NE(parse_error(d).find("rig_dynamics.rig.weights[3]"), std::string::npos) << parse_error(d);
  d = small_scene(false);
  d["rig_dynamics"]["rig"]["bones"][1]["parent"] = "nobody";
  EXPECT_NE(parse_error(d).find("no earlier bone is named"), std::string::npos) << parse_error(d);
  d = small_scene(false);
  d["rig_dynamics"]["keyframes"][1]["pose"] = {0, 1, 2};
  EXPECT_NE(parse_error(d).find("rig_dynamics.keyframes[1].pose"), std::string::npos) << parse_error(d);
}

TEST(RigScene, ShippedArmSceneParses) {
  const std::string path = std::string(::tailor::testing::source_dir()) + "/scenes/rig/arm_jiggle.json";
  const SceneFile file = read_scene_file(path);
  const RigSceneSpec spec = parse_rig_scene(file.node(), file.directory());
  EXPECT_TRUE(spec.reduced);
  EXPECT_EQ(spec.bones.size(), 2u);
  EXPECT_EQ(spec.reduction.example_poses.size(), 3u);
}

}  // namespace
}  // namespace tailor::rig::rig_scene_test
