// `tailor simulate` on scenes with a "dynamics" section: parsing and its errors, the frame
// series and report, and a physical check (a swinging beam with Rayleigh damping loses energy).
#include "problems/fem/dynamic_scene.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../support/report_checks.hpp"
#include "../support/temp_folder.hpp"
#include "problems/fem/dynamic_commands.hpp"
#include "problems/json_text.hpp"
#include "scene_text.hpp"

namespace tailor::dynamic_scene_test {
namespace {

using namespace tailor::testing;

std::string dynamic_box(const std::string& dynamics) {
  std::string text = with(R"("youngs_modulus": 1000, "poisson_ratio": 0.3})",
                          R"("youngs_modulus": 1000, "poisson_ratio": 0.3, "density": 1})");
  return with(R"("solver": {"load_steps": 1})", R"("solver": {"load_steps": 1}, "dynamics": )" + dynamics,
              text);
}

TEST(DynamicScene, ParsesAndReportsErrorsWithKeyPaths) {
  const Scene scene =
      parse_scene(dynamic_box(R"({"scheme": "bdf2", "time_step": 0.05, "steps": 4, "mass": "lumped",
      "rayleigh": {"alpha": 0.1, "beta": 0.01}, "output_every": 2, "initial_velocity": [0, 0.1, 0]})"),
                  "box.json", "");
  ASSERT_TRUE(scene.dynamics);
  EXPECT_EQ(scene.dynamics->scheme, TimeScheme::bdf2);
  EXPECT_EQ(scene.dynamics->steps, 4);
  EXPECT_EQ(scene.dynamics->lumping, MassLumping::lumped);
  EXPECT_DOUBLE_EQ(scene.dynamics->rayleigh_beta, 0.01);
  auto error_of = [](const std::string& dynamics) {
    try {
      parse_scene(dynamic_box(dynamics), "box.json", "");
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of(R"({"time_step": 0.1})").find("dynamics: missing required key \"steps\""),
            std::string::npos);
  EXPECT_NE(error_of(R"({"time_step": -1, "steps": 3})").find("dynamics.time_step"), std::string::npos);
  EXPECT_NE(error_of(R"({"time_step": 0.1, "steps": 3, "scheme": "leapfrog"})").find("dynamics.scheme"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"time_step": 0.1, "steps": 3, "damping": 1})").find("dynamics.damping"),
            std::string::npos);
}

TEST(DynamicScene, SolverSetsTheKeptFactorizationRule) {
  // The time integrator's Newton takes solver.reuse_factorization from the scene [automatic].
  const auto reuse = [](const std::string& key) {
    const std::string text =
        with(R"("solver": {"load_steps": 1})", R"("solver": {"load_steps": 1)" + key + "}",
             dynamic_box(R"({"time_step": 0.05, "steps": 2})"));
    return build_dynamic_scene(parse_scene(text, "box.json", "")).options.newton.reuse_factorization;
  };
  EXPECT_EQ(reuse(""), FactorReuse::automatic);
  EXPECT_EQ(reuse(R"(, "reuse_factorization": false)"), FactorReuse::off);
  EXPECT_EQ(reuse(R"(, "reuse_factorization": true)"), FactorReuse::on);
  EXPECT_EQ(reuse(R"(, "reuse_factorization": "auto")"), FactorReuse::automatic);
}

TEST(DynamicScene, MissingDensityIsASceneError) {
  const Scene scene =
      parse_scene(with(R"("solver": {"load_steps": 1})",
                       R"("solver": {"load_steps": 1}, "dynamics": {"time_step": 0.1, "steps": 2})"),
                  "box.json", "");
  TempFolder folder("dynamic_density");
  EXPECT_THROW(simulate_dynamic_scene(scene, folder.str(), nullptr), SceneError);
}

TEST(DynamicScene, WritesASeriesAndAReportWithDecayingEnergy) {
  // The box released from rest under its end traction swings about the loaded equilibrium;
  // Rayleigh damping makes the total energy (kinetic + potential, loads included) decrease.
  const Scene scene = parse_scene(
      dynamic_box(
          R"({"scheme": "newmark", "time_step": 0.05, "steps": 20, "rayleigh": {"alpha": 0.5, "beta": 0.01},
          "output_every": 5})"),
      "box.json", "");
  TempFolder folder("dynamic_series");
  const DynamicRun run = simulate_dynamic_scene(scene, folder.str(), nullptr);
  EXPECT_TRUE(run.completed) << run.message;
  EXPECT_EQ(run.steps_done, 20);
  for (int frame : {0, 5, 10, 15, 20}) {
    char name[32];
    std::snprintf(name, sizeof(name), "frames/frame_%05d.vtu", frame);
    EXPECT_TRUE(std::filesystem::exists(folder / name)) << name;
  }
  std::ifstream in(run.report_path);
  const nlohmann::json report = parse_json(in);
  testing::expect_report_header(run.report_path);
  EXPECT_EQ(report["kind"], "dynamics");
  EXPECT_EQ(report["status"], "completed");
  ASSERT_EQ(report["steps"].size(), 21u);
  const double e0 = report["steps"][0]["total_energy"], e_end = report["steps"][20]["total_energy"];
  EXPECT_LT(e_end, e0);
  for (std::size_t n = 1; n < report["steps"].size(); ++n)
    EXPECT_LE(report["steps"][n]["total_energy"].get<double>(),
              report["steps"][n - 1]["total_energy"].get<double>() + 1e-9);
  std::ifstream pvd(run.series_path);
  const std::string series((std::istreambuf_iterator<char>(pvd)), std::istreambuf_iterator<char>());
  EXPECT_NE(series.find("frames/frame_00020.vtu"), std::string::npos);
}

TEST(DynamicScene, GradcheckOfATrajectoryObjectivePasses) {
  const Scene scene = parse_scene(
      dynamic_box(
          R"({"scheme": "bdf2", "time_step": 0.05, "steps": 12, "rayleigh": {"alpha": 0.5, "beta": 0.01},
          "objective": {"vertices": {"plane": {"axis": "x", "value": 2}}, "steps": [6, 12], "target": [0.01, 0, 0]}})"),
      "box.json", "");
  TempFolder folder("dynamic_gradcheck");
  const GradcheckRun run = gradcheck_dynamic_scene(scene, folder.str(), 1, nullptr);
  EXPECT_TRUE(run.passed()) << run.gradient.table();
  EXPECT_TRUE(std::filesystem::exists(run.report_path));
  const Scene no_objective = parse_scene(dynamic_box(R"({"time_step": 0.05, "steps": 2})"), "box.json", "");
  EXPECT_THROW(gradcheck_dynamic_scene(no_objective, folder.str(), 1, nullptr), SceneError);
}

TEST(DynamicScene, ExampleSceneParses) {
  const Scene scene = read_scene(kScenesDir + "/swinging_beam.json");
  ASSERT_TRUE(scene.dynamics);
  EXPECT_EQ(scene.dynamics->scheme, TimeScheme::newmark);
}

}  // namespace
}  // namespace tailor::dynamic_scene_test
