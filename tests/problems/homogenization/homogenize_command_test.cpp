// The periodic-cell scene and `tailor homogenize`: parsing, errors with context, outputs.
#include "problems/homogenization/homogenize_command.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../../support/report_checks.hpp"
#include "../../support/temp_folder.hpp"
#include "forward/homogenization/engineering_constants.hpp"
#include "problems/fem/scene.hpp"
#include "problems/json_text.hpp"
#include "problems/metamaterial/metamaterial_scene.hpp"
#include "problems/scene_kinds.hpp"
#include "problems/scene_node.hpp"

namespace tailor::homogenize_command_test {
namespace {

std::string write_scene(const std::string& name, const std::string& text) {
  const auto dir = testing::unique_temp_path("tailor_homogenize_test");
  std::filesystem::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path) << text;
  return path;
}

// The cell scene file as `tailor homogenize` reads it.
CellScene read_cell_scene(const std::string& path) {
  const SceneFile file = read_scene_file(path);
  CellScene scene = parse_cell_scene(file.node(), file.directory());
  scene.name = file.name();
  return scene;
}

std::string kind_of(const std::string& path) {
  return recognise_scene_kind(read_scene_file(path).document).name;
}

const char* const kLayered = R"({
  "type": "periodic_cell",
  "cell": {"lattice": [[1, 0], [0, 1]], "grid": [2, 10], "split": "crossed"},
  "plane": "stress",
  "materials": [{"youngs_modulus": 1, "poisson_ratio": 0.3}, {"youngs_modulus": 10, "poisson_ratio": 0.3}],
  "phases": [{"phase": 1, "slab": {"axis": 1, "from": 0.0, "to": 0.5}}],
  "directions": 8
})";

TEST(HomogenizeCommand, LayeredCellReportAndOutputs) {
  const std::string path = write_scene("layered.json", kLayered);
  ASSERT_EQ(kind_of(path), "periodic_cell");
  const CellScene scene = read_cell_scene(path);
  EXPECT_EQ(scene.name, "layered");
  EXPECT_EQ(scene.source, path);
  EXPECT_EQ(scene.plane, PlaneMode::plane_stress);
  const std::string out = (testing::unique_temp_path("tailor_homogenize_test") / "out").string();
  const HomogenizeRun run = homogenize_scene(scene, out, nullptr);
  // Along the layers the plane-stress moduli add (Voigt): E_x = (1 + 10) / 2 for equal nu.
  EXPECT_NEAR(directional_youngs_modulus(run.compliance, Vector{{1.0, 0.0}}), 5.5, 1e-12);
  // Across them the Reuss (harmonic) and Voigt means bound E_y (Hill 1952); the in-plane
  // constraint between the layers makes it stiffer than the harmonic mean.
  const double E_y = directional_youngs_modulus(run.compliance, Vector{{0.0, 1.0}});
  EXPECT_GT(E_y, 1.0 / 0.55);
  EXPECT_LT(E_y, 5.5);
  std::ifstream in(out + "/report.json");
  const nlohmann::json report = parse_json(in);
  EXPECT_EQ(report["status"], "ok");
  EXPECT_EQ(report["stiffness"].size(), 3u);
  EXPECT_EQ(report["directional"][0]["youngs_modulus"].size(), 9u);
  EXPECT_NEAR(report["volume_fractions"][1].get<double>(), 0.5, 1e-12);
  testing::expect_report_header(out + "/report.json");
  for (const char* file : {"youngs_modulus_polar.png", "poisson_ratio.png", "load_case_11.vtu",
                           "load_case_22.vtu", "load_case_12.vtu"})
    EXPECT_TRUE(std::filesystem::exists(out + "/" + file)) << file;
}

TEST(HomogenizeCommand, ErrorsNameTheKey) {
  std::string text = kLayered;
  const auto expect_error = [](const std::string& scene_text, const std::string& fragment) {
    try {
      read_cell_scene(write_scene("bad.json", scene_text));
      ADD_FAILURE() << "accepted: " << fragment;
    } catch (const SceneError& e) {
      EXPECT_THAT(e.what(), ::testing::HasSubstr(fragment));
    }
  };
  expect_error(std::string(kLayered).replace(std::string(kLayered).find("\"phase\": 1"), 10, "\"phase\": 5"),
               "phases[0].phase");
  expect_error(std::string(kLayered).replace(std::string(kLayered).find("[0, 1]]"), 7, "[1, 0]]"),
               "cell.lattice");
  expect_error(std::string(kLayered).replace(std::string(kLayered).find("\"grid\""), 6, "\"grd\""), "grd");
  // A mesh file that is not periodic: the periodicity error names the vertex.
  const std::string mesh =
      write_scene("skew.mesh",
                  "MeshVersionFormatted 1\nDimension 2\nVertices\n4\n0 0 0\n1 0 0\n1.1 1 0\n0 1 0\n"
                  "Triangles\n2\n1 2 3 0\n1 3 4 0\nEnd\n");
  expect_error(R"({"type": "periodic_cell", "cell": {"lattice": [[1, 0], [0, 1]], "mesh": "skew.mesh"},
                   "materials": [{"youngs_modulus": 1, "poisson_ratio": 0.3}]})",
               "vertex 2 at");
}

TEST(HomogenizeCommand, MaterialsKeyedByTheMeshFilesRegionTags) {
  // A unit square of two triangles tagged 1 and 2 in the file, as Gmsh's physical tags start
  // at 1: materials name their tag, in any order, and need no entry for a region 0.
  write_scene("tagged.mesh",
              "MeshVersionFormatted 1\nDimension 2\nVertices\n4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
              "Triangles\n2\n1 2 3 1\n1 3 4 2\nEnd\n");
  const auto scene_with = [](const std::string& materials) {
    return R"({"type": "periodic_cell", "cell": {"lattice": [[1, 0], [0, 1]], "mesh": "tagged.mesh"},
               "materials": )" +
           materials + "}";
  };
  const CellScene scene = read_cell_scene(
      write_scene("tagged.json", scene_with(R"([{"region": 2, "youngs_modulus": 10, "poisson_ratio": 0.3},
                                   {"region": 1, "youngs_modulus": 1, "poisson_ratio": 0.3}])")));
  EXPECT_EQ(scene.element_phase, (std::vector<int>{1, 0}));
  EXPECT_EQ(scene.youngs_modulus(), (Vector{{1.0, 10.0}}));
  const auto expect_error = [&](const std::string& materials, const std::string& fragment) {
    try {
      read_cell_scene(write_scene("tagged_bad.json", scene_with(materials)));
      ADD_FAILURE() << "accepted: " << materials;
    } catch (const SceneError& e) {
      EXPECT_THAT(e.what(), ::testing::HasSubstr(fragment));
    }
  };
  // The index form still works, and says what to do when a tag has no material.
  expect_error(
      R"([{"youngs_modulus": 1, "poisson_ratio": 0.3}, {"youngs_modulus": 2, "poisson_ratio": 0.3}])",
      "element 1 has region 2 but there are 2 materials");
  expect_error(R"([{"region": 1, "youngs_modulus": 1, "poisson_ratio": 0.3}])",
               "materials: element 1 has region 2, which no material names");
  expect_error(
      R"([{"region": 1, "youngs_modulus": 1, "poisson_ratio": 0.3}, {"youngs_modulus": 2, "poisson_ratio": 0.3}])",
      "materials[1]: either every material names its \"region\" or none does");
  expect_error(
      R"([{"region": 1, "youngs_modulus": 1, "poisson_ratio": 0.3}, {"region": 1, "youngs_modulus": 2, "poisson_ratio": 0.3}])",
      "materials[1].region: region 1 is already materials[0]");
}

TEST(HomogenizeCommand, PlateLikeCellReportsTheBendingStiffness) {
  const std::string path = write_scene("plate.json", R"({
    "type": "periodic_cell",
    "cell": {"lattice": [[1, 0, 0], [0, 1, 0], [0, 0, 0.5]], "grid": [4, 4, 2], "periodic": [true, true, false]},
    "materials": [{"youngs_modulus": 2, "poisson_ratio": 0.3}],
    "directions": 8
  })");
  const std::string out = (testing::unique_temp_path("tailor_homogenize_test") / "plate").string();
  const HomogenizeRun run = homogenize_scene(read_cell_scene(path), out, nullptr);
  // Same mesh as the coarsest of PlateBending.HomogeneousPlateConvergesToKirchhoffTheory: the
  // Kirchhoff value 2 * 0.5^3 / (12 * 0.91) times (1 + its relative error there).
  EXPECT_GT(run.result.stiffness(0, 0), 2.0 * 0.125 / (12.0 * 0.91));
  std::ifstream in(out + "/report.json");
  const nlohmann::json report = parse_json(in);
  EXPECT_EQ(report["mode"], "plate_bending");
  EXPECT_EQ(report["directional_bending"]["bending_stiffness"].size(), 9u);
  testing::expect_report_header(out + "/report.json");
  EXPECT_TRUE(std::filesystem::exists(out + "/bending_stiffness_polar.png"));
  const std::string bad = write_scene("plate_bad.json", R"({
    "type": "periodic_cell",
    "cell": {"lattice": [[1, 0, 0], [0, 1, 0], [0, 0, 0.5]], "grid": [2, 2, 2], "periodic": [false, true, true]},
    "materials": [{"youngs_modulus": 2, "poisson_ratio": 0.3}]
  })");
  EXPECT_THROW(read_cell_scene(bad), SceneError);
}

TEST(MetamaterialScene, SmallDesignRunsAndReportsTheRechecks) {
  const std::string path = write_scene("design.json", R"({
    "type": "periodic_cell",
    "cell": {"lattice": [[1, 0], [0, 1]], "grid": [8, 8]},
    "plane": "stress",
    "materials": [{"youngs_modulus": 1, "poisson_ratio": 0.3}],
    "design": {
      "material": {"youngs_modulus": 1, "poisson_ratio": 0.3},
      "filter_radius": 0.2, "max_volume_fraction": 0.5, "initial_density": [0.5], "perturbation": 0.2,
      "objective": {"directional_stiffness": {"directions": [[1, 0], [0, 1]], "targets": [0.2, 0.05]}},
      "projection": [0, 4],
      "optimizer": {"max_iterations": 5}
    }
  })");
  ASSERT_EQ(kind_of(path), "cell_design");
  const std::string out = (testing::unique_temp_path("tailor_homogenize_test") / "design").string();
  const SceneFile file = read_scene_file(path);
  const CellScene cell = parse_cell_scene(file.node(), file.directory());
  const MetamaterialRun run =
      run_metamaterial_design(cell, parse_metamaterial_design(file.node(), cell), out, nullptr, nullptr);
  EXPECT_EQ(run.stiffness_thresholded.rows(), 3);
  EXPECT_EQ(run.stiffness_refined.rows(), 3);
  std::ifstream in(out + "/report.json");
  const nlohmann::json report = parse_json(in);
  for (const char* key :
       {"gray", "thresholded", "refined_thresholded", "history", "timings", "filter_radius"})
    EXPECT_TRUE(report.contains(key)) << key;
  EXPECT_EQ(report["refined_thresholded"]["elements"], 4 * 128);
  EXPECT_LE(report["volume_fraction"].get<double>(), 0.5 + 1e-6);
  EXPECT_TRUE(std::filesystem::exists(out + "/design.png"));
  testing::expect_report_header(out + "/report.json");
  EXPECT_EQ(kind_of(write_scene("plain.json", kLayered)), "periodic_cell");
}

}  // namespace
}  // namespace tailor::homogenize_command_test
