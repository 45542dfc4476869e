// What the command line checks before any solve, and the warnings it gives (issue "robust on
// ordinary inputs"): the output folder (a file, a folder another run holds, tidying a folder made
// for a refused run), meshes with vertices no element uses, --hessian where a kind has no
// Hessian-vector products, output sizes (dynamic frames, a metamaterial's refined check), and
// the physics warnings (Poisson's ratio near 1/2 on linear elements, Newmark with a step above
// the body's longest period). Each runs bin/tailor as a user would.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>

#include "../support/temp_folder.hpp"
#include "../support/text_files.hpp"
#include "problems/output_folder.hpp"
#include "problems/scene_error.hpp"
#include "tests/support/test_paths.hpp"

namespace tailor::run_guards_test {
namespace {

namespace fs = std::filesystem;
using tailor::testing::TempFolder;

const std::string kScenes = tailor::testing::kScenesDir;

using tailor::testing::read_file;
using tailor::testing::write_file;

nlohmann::json read_json(const std::string& path) { return nlohmann::json::parse(read_file(path)); }

// Runs bin/tailor; returns its exit code, with stdout and stderr in `output`.
int run_cli(const std::string& arguments, const TempFolder& folder, std::string& output) {
  const std::string log = folder / "log";
  const std::string command =
      std::string(::tailor::testing::binary_dir()) + "/bin/tailor " + arguments + " > " + log + " 2>&1";
  const int status = std::system(command.c_str());
  output = read_file(log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(OutputFolderGuard, AFileAsOutIsRefusedBeforeTheSolve) {
  TempFolder folder("guard_file");
  write_file(folder / "taken", "not a folder");
  std::string output;
  EXPECT_EQ(run_cli("simulate " + kScenes + "/cantilever.json --out " + (folder / "taken"), folder, output), 2);
  EXPECT_TRUE(contains(output, "output folder '" + (folder / "taken") + "' is a file")) << output;
  EXPECT_FALSE(contains(output, "Newton")) << output;  // nothing was solved
  EXPECT_EQ(read_file(folder / "taken"), "not a folder");
}

TEST(OutputFolderGuard, ASecondRunIntoAHeldFolderIsRefusedNamingTheHolder) {
  TempFolder folder("guard_lock");
  const std::string out = folder / "out";
  std::string output;
  {
    OutputFolder held(out, "tailor run first.json");  // this process holds the folder
    EXPECT_EQ(run_cli("simulate " + kScenes + "/cantilever.json --out " + out, folder, output), 2);
    EXPECT_TRUE(contains(output, "is in use by another run (process " + std::to_string(::getpid()) +
                                     ", 'tailor run first.json', since "))
        << output;
    EXPECT_FALSE(fs::exists(out + "/report.json"));
    // In this process too: a second claim fails while the first holds.
    EXPECT_THROW(OutputFolder(out, "again"), SceneError);
  }
  // Released (as when the holder ends, however it ends): the folder can be claimed again.
  EXPECT_EQ(run_cli("simulate " + kScenes + "/cantilever.json --out " + out, folder, output), 0) << output;
  EXPECT_TRUE(fs::exists(out + "/report.json"));
}

TEST(OutputFolderGuard, ARefusedSceneLeavesNoFolderItCreated) {
  TempFolder folder("guard_tidy");
  write_file(folder / "bad.json", R"({"mesh": {"box": {"min": [0, 0, 0], "max": [1, 1, 1], "cells": [1, 1, 1]}},
    "materials": [{"elements": "all", "model": "linear", "youngs_modulus": -1, "poisson_ratio": 0.3}]})");
  std::string output;
  EXPECT_EQ(run_cli("simulate " + (folder / "bad.json") + " --out " + (folder / "new"), folder, output), 2);
  EXPECT_TRUE(contains(output, "youngs_modulus")) << output;
  EXPECT_FALSE(fs::exists(folder / "new"));
  // A folder that existed before stays.
  fs::create_directories(folder / "old");
  EXPECT_EQ(run_cli("simulate " + (folder / "bad.json") + " --out " + (folder / "old"), folder, output), 2);
  EXPECT_TRUE(fs::is_directory(folder / "old"));
}

TEST(CommandLine, FlagErrorsAreInTailorsWordsNotTheParsers) {
  TempFolder folder("guard_flags");
  std::string output;
  EXPECT_EQ(run_cli("simulate " + kScenes + "/cantilever.json --out a --out b", folder, output), 2);
  EXPECT_TRUE(contains(output, "tailor: --out takes one value; it was given 2")) << output;
  EXPECT_FALSE(contains(output, "At Most")) << output;
  EXPECT_EQ(run_cli("simulate " + kScenes + "/cantilever.json --out", folder, output), 2);
  EXPECT_TRUE(contains(output, "tailor: --out needs a value")) << output;
  EXPECT_FALSE(contains(output, "required")) << output;
}

// A Medit mesh of one tet and a fifth vertex no element uses (a geometry point saved with it).
const char* kMeshWithAStrayVertex = R"(MeshVersionFormatted 2
Dimension
3
Vertices
5
0 0 0 0
1 0 0 0
0 1 0 0
0 0 1 0
5 5 5 0
Tetrahedra
1
1 2 3 4 0
End
)";

TEST(MeshInput, AVertexNoElementUsesIsRefusedNamingItInEveryVerb) {
  TempFolder folder("guard_stray");
  write_file(folder / "stray.mesh", kMeshWithAStrayVertex);
  write_file(folder / "scene.json", R"({"mesh": {"file": "stray.mesh"},
    "materials": [{"elements": "all", "model": "linear", "youngs_modulus": 1e6, "poisson_ratio": 0.3, "density": 1}],
    "dirichlet": [{"vertices": {"plane": {"axis": "z", "value": 0}}}],
    "loads": {"gravity": [0, 0, -9.81]}})");
  for (const std::string& verb : {"simulate --out " + (folder / "out"), "modes --out " + (folder / "out"),
                                  std::string("check")}) {
    std::string output;
    EXPECT_EQ(run_cli(verb + " " + (folder / "scene.json"), folder, output), 2)
        << verb << ": " << output;
    EXPECT_TRUE(contains(output, "stray.mesh: 1 of 5 vertices are used by no element (0-based: 4)"))
        << verb << ": " << output;
  }
}

TEST(HessianFlag, KindsWithoutHessianVectorProductsRefuseItBeforeAnySolve) {
  TempFolder folder("guard_hessian");
  std::string output;
  // A handle's force term has no second derivatives.
  EXPECT_EQ(run_cli("gradcheck " + kScenes + "/cantilever_handle.json --hessian --out " + (folder / "a"), folder,
                    output),
            2);
  EXPECT_TRUE(contains(output, "cantilever_handle.json: --hessian: this inverse problem has no Hessian-vector"))
      << output;
  EXPECT_FALSE(contains(output, "Taylor")) << output;  // refused before the gradient's check
  EXPECT_FALSE(fs::exists(folder / "a"));
  EXPECT_EQ(run_cli("gradcheck " + kScenes + "/contact/box_on_ground.json --hessian --out " + (folder / "b"),
                    folder, output),
            2);
  EXPECT_TRUE(contains(output, "--hessian: the design functionals of rigid-body scenes")) << output;
  EXPECT_EQ(run_cli("gradcheck " + kScenes + "/swinging_beam.json --hessian --out " + (folder / "c"), folder,
                    output),
            2);
  EXPECT_TRUE(contains(output, "--hessian: the time-dependent adjoint")) << output;
}

nlohmann::json swinging_beam() { return read_json(kScenes + "/swinging_beam.json"); }

TEST(OutputSize, FramesThatWouldNotFitTheDiskAreRefusedBeforeTheFirstStep) {
  TempFolder folder("guard_frames");
  nlohmann::json scene = swinging_beam();
  scene["dynamics"]["steps"] = 2000000000;
  scene["dynamics"]["output_every"] = 1;
  write_file(folder / "long.json", scene.dump());
  std::string output;
  EXPECT_EQ(run_cli("simulate " + (folder / "long.json") + " --out " + (folder / "out"), folder, output), 2);
  EXPECT_TRUE(contains(output, "long.json: dynamics.steps / output_every: 2000000001 frames of")) << output;
  EXPECT_TRUE(contains(output, "free on the output disk")) << output;
  EXPECT_FALSE(contains(output, "step 1/")) << output;
}

TEST(OutputSize, AMetamaterialsRefinedCheckIsBoundedWhenTheSceneIsRead) {
  TempFolder folder("guard_refine");
  nlohmann::json scene = read_json(kScenes + "/homogenization/auxetic_2d.json");
  ASSERT_TRUE(scene.contains("design"));
  scene["design"]["refine"] = 500;
  write_file(folder / "fine.json", scene.dump());
  std::string output;
  EXPECT_EQ(run_cli("run " + (folder / "fine.json") + " --out " + (folder / "out"), folder, output), 2);
  EXPECT_TRUE(contains(output, "fine.json: design.refine: the refined check would solve a cell of")) << output;
  scene["design"]["refine"] = 2;
  scene["design"]["filter_radius"] = 100.0;
  write_file(folder / "wide.json", scene.dump());
  EXPECT_EQ(run_cli("run " + (folder / "wide.json") + " --out " + (folder / "out"), folder, output), 2);
  EXPECT_TRUE(contains(output, "wide.json: design.filter_radius: at most half the shortest lattice vector"))
      << output;
  EXPECT_FALSE(contains(output, "DensityFilter")) << output;
}

TEST(PhysicsWarnings, NearlyIncompressibleLinearElementsAreWarnedAbout) {
  TempFolder folder("guard_locking");
  nlohmann::json scene = read_json(kScenes + "/cantilever.json");
  scene["materials"][0]["poisson_ratio"] = 0.4999;
  write_file(folder / "rubber.json", scene.dump());
  std::string output;
  run_cli("simulate " + (folder / "rubber.json") + " --out " + (folder / "out"), folder, output);
  EXPECT_TRUE(contains(output, "warning: " + (folder / "rubber.json") + ": materials[0].poisson_ratio: 0.4999 on "
                                   "linear elements"))
      << output;
  // The same scene at 0.3: no warning (the check can tell).
  scene["materials"][0]["poisson_ratio"] = 0.3;
  write_file(folder / "steel.json", scene.dump());
  run_cli("simulate " + (folder / "steel.json") + " --out " + (folder / "out2"), folder, output);
  EXPECT_FALSE(contains(output, "warning:")) << output;
}

// The swinging beam (4 x 0.5 x 0.5, E = 2e5, density 100) has a longest period of about 4.4 s
// (Euler-Bernoulli: omega_1 = 1.875^2 sqrt(E I / (rho A L^4)) = 1.42 rad/s). Its shipped step 0.01
// resolves it; a step of 10 s resolves nothing.
TEST(PhysicsWarnings, NewmarkWithAStepAboveTheLongestPeriodIsWarnedAbout) {
  TempFolder folder("guard_newmark");
  nlohmann::json scene = swinging_beam();
  scene["dynamics"]["time_step"] = 10.0;
  scene["dynamics"]["steps"] = 2;
  scene["dynamics"].erase("objective");
  write_file(folder / "coarse.json", scene.dump());
  std::string output;
  EXPECT_EQ(run_cli("simulate " + (folder / "coarse.json") + " --out " + (folder / "out"), folder, output), 0)
      << output;
  EXPECT_TRUE(contains(output, "warning: " + (folder / "coarse.json") + ": dynamics.time_step: h = 10 is")) << output;
  // The period printed is the coarse mesh's (2 x 2 cells of linear tets, stiffer in bending than
  // the beam): within 30% of Euler-Bernoulli's 4.4 s.
  std::smatch period;
  ASSERT_TRUE(std::regex_search(output, period, std::regex(R"(longest natural period \(([0-9.]+)\))"))) << output;
  EXPECT_NEAR(std::stod(period[1]), 4.4, 0.3 * 4.4) << output;
  const nlohmann::json report = read_json(folder / "out/report.json");
  ASSERT_EQ(report["warnings"].size(), 1u) << report.dump();
  scene["dynamics"]["time_step"] = 0.01;
  write_file(folder / "fine.json", scene.dump());
  EXPECT_EQ(run_cli("simulate " + (folder / "fine.json") + " --out " + (folder / "out2"), folder, output), 0)
      << output;
  EXPECT_FALSE(contains(output, "warning:")) << output;
  EXPECT_TRUE(read_json(folder / "out2/report.json")["warnings"].empty());
}

}  // namespace
}  // namespace tailor::run_guards_test
