// The inverse verbs through the C++ API: gradient checks of the example scenes and of every
// term and design map, recovery of the two-material bar's moduli, observations from a file,
// and the documented report.json / gradcheck.json keys (also when the optimizer stops early).
#include "problems/fem/inverse_commands.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "../support/report_checks.hpp"
#include "../support/temp_folder.hpp"
#include "../support/text_files.hpp"
#include "problems/json_text.hpp"
#include "scene_text.hpp"

namespace tailor::inverse_commands_test {
namespace {

namespace fs = std::filesystem;

const std::string kScenes = tailor::testing::kScenesDir;

using TempFolder = tailor::testing::TempFolder;

using tailor::testing::read_file;
// small_box_scene() (linear, E = 1000, pulled along x) with an inverse section.
Scene box_scene(const std::string& inverse, const std::string& directory = "") {
  return parse_scene(testing::with("\"solver\": {\"load_steps\": 1}",
                                   "\"solver\": {\"load_steps\": 1},\n  \"inverse\": " + inverse),
                     "box.json", directory);
}

TEST(InverseGradcheck, ExampleScenesPassAndWriteTheirJson) {
  TempFolder folder("inverse_gradcheck");
  for (const char* name : {"two_material_bar_inverse", "plate_stripe_inverse"}) {
    SCOPED_TRACE(name);
    const GradcheckRun run = gradcheck_scene(read_scene(kScenes + "/" + name + ".json"), folder / name, {});
    EXPECT_TRUE(run.passed()) << run.gradient.table();
    EXPECT_EQ(run.gradient.status, TaylorStatus::passed);
    EXPECT_GE(run.gradient.rate1, 1.9) << run.gradient.table();
    EXPECT_FALSE(run.hessian);
    const auto json = parse_json(read_file(folder / (std::string(name) + "/gradcheck.json")));
    EXPECT_EQ(json["status"], "passed");
    EXPECT_EQ(json["passed"], true);
    EXPECT_EQ(json["scene"]["name"], name);
    EXPECT_EQ(json["design_size"], run.design_size);
    EXPECT_EQ(json["seed"], 1);
    EXPECT_GE(json["rate1"].get<double>(), 1.9);
    std::size_t judged = 0;  // the search rows come first, then the judged halvings
    for (const auto& row : json["rows"]) judged += row["judged"].get<bool>() ? 1 : 0;
    EXPECT_EQ(judged, static_cast<std::size_t>(TaylorTestOptions{}.halvings + 1));
    EXPECT_TRUE(json.contains("tailor_version"));
    EXPECT_FALSE(json.contains("hessian"));
  }
}

TEST(InverseGradcheck, HessianCheckAndSeedOverride) {
  TempFolder folder("inverse_gradcheck_hessian");
  const GradcheckRun run =
      gradcheck_scene(read_scene(kScenes + "/two_material_bar_inverse.json"), folder / "out", {7u, true});
  EXPECT_EQ(run.seed, 7u);
  ASSERT_TRUE(run.hessian);
  EXPECT_TRUE(run.passed()) << run.gradient.table() << run.hessian->table();
  EXPECT_GE(run.hessian->rate1, 1.9) << run.hessian->table();
  const auto json = parse_json(read_file(folder / "out/gradcheck.json"));
  testing::expect_report_header(folder / "out/gradcheck.json");
  EXPECT_EQ(json["seed"], 7);
  EXPECT_EQ(json["hessian"]["status"], "passed");
}

// Every term type and both maps, on the small box (per element) and the two-region cube. The
// weights keep the terms on comparable scales (the value smoothness is in units of E^2, E ~ 800):
// a term whose curvature dwarfs the first-order change leaves the Taylor test no step that is
// both asymptotic and above the forward solve's round-off.
TEST(InverseGradcheck, EveryTermAndDesignMapPasses) {
  TempFolder folder("inverse_gradcheck_terms");
  const Scene identity = box_scene(R"({
    "design": {"parameter": "youngs_modulus", "granularity": "per_element", "map": "identity", "min": 10,
               "initial": 800},
    "objective": [
      {"type": "target_displacements", "vertices": {"plane": {"axis": "x", "value": 2}}, "displacement": [0.01, 0, 0]},
      {"type": "synthetic_observations", "vertices": {"list": [10, 20, 30]}, "youngs_modulus": 1000, "noise": 0.01},
      {"type": "smoothness", "weight": 1e-9, "on": "value", "weighting": "facet"},
      {"type": "smoothness", "weight": 1e-2, "on": "log"},
      {"type": "tikhonov", "weight": 1e-2, "prior": 1000}
    ]
  })");
  const GradcheckRun by_element = gradcheck_scene(identity, folder / "identity", {});
  EXPECT_TRUE(by_element.passed()) << by_element.gradient.table();

  std::string cube = read_file(kScenes + "/cube_regions.json");
  cube.replace(cube.rfind('}'), 1, R"(,
    "inverse": {
      "design": {"parameter": "youngs_modulus", "granularity": "per_region", "initial": 3e5},
      "objective": [{"type": "synthetic_observations", "vertices": {"plane": {"axis": "z", "value": 1}},
                     "youngs_modulus": {"materials": [1e5, 1e6]}}]
    }
  })");
  const GradcheckRun by_region =
      gradcheck_scene(parse_scene(cube, "cube.json", kScenes), folder / "region", {});
  EXPECT_EQ(by_region.design_size, 2);
  EXPECT_TRUE(by_region.passed()) << by_region.gradient.table();
}

TEST(InverseGradcheck, FailedForwardSolveIsAStatusNotAnException) {
  TempFolder folder("inverse_gradcheck_failed");
  // One Newton iteration cannot converge a large Neo-Hookean stretch.
  std::string json = testing::with("\"model\": \"linear\"", "\"model\": \"neo_hookean\"");
  json = testing::with("\"traction\": [1, 0, 0]", "\"traction\": [300, 0, 0]", json);
  json = testing::with("\"load_steps\": 1", "\"load_steps\": 1, \"max_iterations\": 1", json);
  json = testing::with("\"solver\"", R"("inverse": {
    "design": {"parameter": "youngs_modulus", "granularity": "per_material"},
    "objective": [{"type": "target_displacements", "vertices": {"list": [4]}, "displacement": [0.5, 0, 0]}]
  },
  "solver")",
                       json);
  const GradcheckRun run = gradcheck_scene(parse_scene(json, "box.json", ""), folder / "out", {});
  EXPECT_FALSE(run.passed());
  EXPECT_EQ(run.gradient.status, TaylorStatus::evaluation_failed) << run.gradient.table();
  EXPECT_EQ(parse_json(read_file(folder / "out/gradcheck.json"))["status"], "evaluation_failed");
}

TEST(InverseRun, TwoMaterialBarRecoversBothModuli) {
  TempFolder folder("inverse_run_bar");
  const InverseRun run =
      run_inverse_scene(read_scene(kScenes + "/two_material_bar_inverse.json"), folder / "out");
  ASSERT_TRUE(run.result.converged()) << run.result.report();
  ASSERT_EQ(run.design_values.size(), 2);
  EXPECT_NEAR(run.design_values[0] / 1e5, 1.0, 1e-6) << run.design_values[0];
  EXPECT_NEAR(run.design_values[1] / 3e5, 1.0, 1e-6) << run.design_values[1];
  ASSERT_TRUE(run.error);
  EXPECT_LT(run.error->relative_l2, 1e-6);
  EXPECT_GT(run.initial_error->relative_l2, 0.5);  // the start was 3x off

  testing::expect_report_header(folder / "out/report.json");
  const auto report = parse_json(read_file(folder / "out/report.json"));
  for (const char* key : {"tailor_version", "report_format", "kind", "scene", "status", "message",
                          "converged", "backend", "iterations", "evaluations", "history", "objective",
                          "solves", "design", "ground_truth", "timings", "mesh"})
    EXPECT_TRUE(report.contains(key)) << key;
  EXPECT_EQ(report["kind"], "inverse");
  EXPECT_EQ(report["status"], "converged");
  EXPECT_EQ(report["converged"], true);
  EXPECT_EQ(report["backend"], "nlopt_lbfgs");
  const auto& history = report["history"];
  ASSERT_EQ(history.size(), static_cast<std::size_t>(report["iterations"].get<int>() + 1));
  for (const char* key :
       {"iteration", "objective", "gradient_norm", "step", "seconds", "forward_solves", "adjoint_solves"})
    EXPECT_TRUE(history.back()[key].is_number()) << key;
  EXPECT_GT(history.front()["objective"].get<double>(), 1e3 * history.back()["objective"].get<double>());
  EXPECT_EQ(report["objective"]["initial"], history.front()["objective"]);
  EXPECT_LT(report["objective"]["final"].get<double>(), 1e-12);
  EXPECT_EQ(report["objective"]["terms"][0]["type"], "synthetic_observations");
  EXPECT_GE(report["solves"]["forward"].get<int>(), history.back()["forward_solves"].get<int>());
  const auto& design = report["design"];
  EXPECT_EQ(design["granularity"], "per_material");
  EXPECT_EQ(design["map"], "log");
  EXPECT_EQ(design["size"], 2);
  EXPECT_EQ(design["labels"][1], "materials[1]");
  EXPECT_NEAR(design["values"][1].get<double>(), 3e5, 0.3);
  for (const char* key : {"min", "max", "mean"}) EXPECT_TRUE(design["final"][key].is_number()) << key;
  EXPECT_NEAR(design["final"]["min"].get<double>(), 1e5, 0.1);
  EXPECT_LT(report["ground_truth"]["relative_l2_error"].get<double>(), 1e-6);
  EXPECT_EQ(report["ground_truth"]["source"], "inverse.objective[0].youngs_modulus");
  for (const char* key : {"total", "setup", "optimization", "forward", "adjoint", "output"})
    EXPECT_TRUE(report["timings"][key].is_number()) << key;

  const std::string vtu = read_file(folder / "out/result.vtu");
  for (const char* field : {"\"youngs_modulus\"", "\"youngs_modulus_initial\"", "\"youngs_modulus_true\"",
                            "\"youngs_modulus_relative_error\"", "\"displacement\""})
    EXPECT_NE(vtu.find(field), std::string::npos) << field;
}

TEST(InverseRun, ObservationsFromAFileRecoverTheModulus) {
  TempFolder folder("inverse_run_observations");
  // Observe the pulled end of the box at its true modulus (1000), then start from 3000.
  const Scene truth = parse_scene(testing::small_box_scene(), "box.json", "");
  const StaticSetup setup = setup_static_scene(truth);
  const StaticSolution solution = solve_static(setup);
  ASSERT_TRUE(solution.converged);
  {
    std::ofstream out(folder / "end.txt");
    out.precision(17);
    out << "# vertex ux uy uz\n";
    for (int v = 0; v < setup.mesh.num_vertices(); ++v)
      if (setup.mesh.rest_positions(v, 0) == 2.0) out << v << " " << solution.displacement.row(v) << "\n";
  }
  const Scene scene = box_scene(R"({
    "design": {"parameter": "youngs_modulus", "granularity": "per_material", "initial": 3000},
    "objective": [{"type": "observations", "file": "end.txt"}],
    "ground_truth": {"youngs_modulus": 1000}
  })",
                                folder / "");
  const InverseRun run = run_inverse_scene(scene, folder / "out");
  ASSERT_TRUE(run.result.converged()) << run.result.report();
  EXPECT_NEAR(run.design_values[0] / 1000.0, 1.0, 1e-6);
  EXPECT_EQ(run.problem->truth_key, "inverse.ground_truth.youngs_modulus");
  EXPECT_LT(run.error->relative_l2, 1e-6);
}

TEST(InverseRun, IterationLimitStillWritesTheReport) {
  TempFolder folder("inverse_run_limit");
  std::string json = read_file(kScenes + "/two_material_bar_inverse.json");
  json = testing::with("\"max_iterations\": 100", "\"max_iterations\": 2", json);
  const InverseRun run = run_inverse_scene(parse_scene(json, "bar.json", kScenes), folder / "out");
  EXPECT_EQ(run.result.status, OptimizerStatus::max_iterations) << run.result.report();
  const auto report = parse_json(read_file(folder / "out/report.json"));
  EXPECT_EQ(report["status"], "max_iterations");
  EXPECT_EQ(report["converged"], false);
  EXPECT_EQ(report["iterations"], 2);
  EXPECT_GT(report["ground_truth"]["relative_l2_error"].get<double>(), 1e-3);
  // The best design found, not the last one tried: never worse than the start.
  EXPECT_LE(report["objective"]["final"].get<double>(), report["objective"]["initial"].get<double>());
  EXPECT_TRUE(fs::exists(folder / "out/result.vtu"));
}

}  // namespace
}  // namespace tailor::inverse_commands_test
