// Rods next to an FEM body in one scene (scenes/rods/rods_and_beam.json): one Model and one
// Newton solve for a Neo-Hookean beam and a rod cantilever, which do not interact. Reference:
// each part solved on its own (the static FEM path, solve_static, and the rods path,
// simulate_rods); the combined solve must reproduce both.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../../support/report_checks.hpp"
#include "../../support/temp_folder.hpp"
#include "problems/fem/scene.hpp"
#include "problems/fem/static_scene.hpp"
#include "problems/json_text.hpp"
#include "problems/rods/rod_scene.hpp"
#include "problems/scene_kinds.hpp"
#include "problems/scene_node.hpp"
#include "rod_scene_files.hpp"

namespace tailor::rod_fem_scene_test {
namespace {

using testing::read_json_file;
using testing::rod_scene_path;

const std::string kScene = rod_scene_path("rods_and_beam.json");

TEST(RodFemScene, EachPartMatchesItsSeparateSolve) {
  const nlohmann::json document = read_json_file(kScene);
  const auto dir = testing::unique_temp_path("tailor_rods_and_beam");
  std::filesystem::remove_all(dir);
  const RodFemSimulation both = simulate_rods_with_fem(SceneNode(document, kScene, ""), ".", dir.string());
  ASSERT_TRUE(both.rods.converged);
  EXPECT_TRUE(std::filesystem::exists(both.fem_vtu_path));
  EXPECT_TRUE(std::filesystem::exists(both.rods.vtu_path));
  const nlohmann::json report = read_json_file(both.rods.report_path);
  EXPECT_TRUE(report["energies"].contains("rod_bending"));
  EXPECT_GE(report["energies"].size(), 5u);  // the FEM terms too

  // The FEM part alone.
  nlohmann::json fem = document;
  fem.erase("rods");
  const StaticSetup setup = setup_static_scene(parse_scene(dump_json(fem), "fem", "."));
  const StaticSolution alone = solve_static(setup);
  ASSERT_TRUE(alone.converged);
  const int nf = setup.num_dofs();
  ASSERT_EQ(both.fem_dofs, nf);
  const Vector rest = setup.rest_state();
  const double fem_scale = (alone.positions - rest).lpNorm<Eigen::Infinity>();
  const double fem_error = (both.rods.state.head(nf) - alone.positions).lpNorm<Eigen::Infinity>() / fem_scale;

  // The rod part alone.
  const RodSimulation rod = simulate_rods(parse_rod_scene(document), (dir / "rod_only").string());
  ASSERT_TRUE(rod.converged);
  const int nr = static_cast<int>(rod.state.size());
  const Vector rod_rest = [&] {
    Vector x = rod.state;
    x.setZero();
    for (int v = 0; v < 21; ++v) x[3 * v] = v / 20.0, x[3 * v + 1] = 3.0;
    return x;
  }();
  const double rod_scale = (rod.state - rod_rest).head(63).lpNorm<Eigen::Infinity>();
  const double rod_error = (both.rods.state.tail(nr) - rod.state).lpNorm<Eigen::Infinity>() / rod_scale;
  std::printf(
      "rods and beam in one solve: FEM part error %.2e (of its largest displacement %.3e), "
      "rod part error %.2e (of %.3e)\n",
      fem_error, fem_scale, rod_error, rod_scale);
  EXPECT_GT(fem_scale, 1e-3);
  EXPECT_GT(rod_scale, 1e-3);
  EXPECT_LT(fem_error, 1e-6);
  EXPECT_LT(rod_error, 1e-6);
  std::filesystem::remove_all(dir);
}

TEST(RodFemScene, SimulateEntryPointAndRefusedSections) {
  const auto dir = testing::unique_temp_path("tailor_rods_and_beam_cli");
  std::ostringstream log;
  const SceneFile file = read_scene_file(kScene);
  EXPECT_TRUE(simulate_rod_scene(file.node(), file.directory(), dir.string(), &log)) << log.str();
  testing::expect_report_header((dir / "report.json").string());
  EXPECT_TRUE(std::filesystem::exists(dir / "result.vtu"));
  std::filesystem::remove_all(dir);
  nlohmann::json s = read_json_file(kScene);
  s["load_steps"] = 2;
  const std::string source = "scene";
  EXPECT_THROW(simulate_rods_with_fem(SceneNode(s, source, ""), ".", dir.string()), SceneError);
  s = read_json_file(kScene);
  s["dynamics"] = {{"time_step", 0.1}, {"steps", 1}};
  EXPECT_THROW(simulate_rods_with_fem(SceneNode(s, source, ""), ".", dir.string()), SceneError);
  // Free parts have no equilibrium: refused before solving, each with the static scenes'
  // diagnosis (the body's supports; the rods' clamps and pins).
  s = read_json_file(kScene);
  s.erase("dirichlet");
  const std::string free_beam = "free_beam.json", free_rod = "free_rod.json";
  try {
    simulate_rods_with_fem(SceneNode(s, free_beam, ""), ".", dir.string());
    ADD_FAILURE() << "a free body was solved";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("free to move rigidly"), std::string::npos) << e.what();
  }
  s = read_json_file(kScene);
  s["rods"][0].erase("clamp");
  try {
    simulate_rods_with_fem(SceneNode(s, free_rod, ""), ".", dir.string());
    ADD_FAILURE() << "a free rod was solved";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("free_rod.json: rods[0] (\"rod\"): the supports leave the rod free"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace tailor::rod_fem_scene_test
