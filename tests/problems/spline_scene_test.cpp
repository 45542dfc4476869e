// Spline materials in ordinary scenes ("model": "spline"): the corotated preset reproduces the
// closed-form corotated material (the preset is exact, principal_stretch_curves.hpp), bad
// spline entries fail with their key path, and the curves a material fit writes
// (DIR/material.json) drive a scene that matches the material the fit recovered.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "problems/fem/inverse_commands.hpp"
#include "problems/fem/scene.hpp"
#include "problems/fem/spline_curves_json.hpp"
#include "problems/fem/static_scene.hpp"
#include "problems/json_text.hpp"
#include "problems/material_fit/material_fit.hpp"
#include "scene_text.hpp"
#include "tests/support/temp_folder.hpp"

namespace tailor::spline_scene_test {
namespace {

using testing::small_box_scene;
using testing::with;

const std::string kLinearMaterial = R"("model": "linear", "youngs_modulus": 1000, "poisson_ratio": 0.3)";

// The box of scene_text.hpp with a large load (stretch ~1.25 and bending from a shear traction),
// so the comparison runs well inside the nonlinear range.
std::string loaded_box(const std::string& material) {
  return with("\"traction\": [1, 0, 0]", "\"traction\": [250, 40, 0]", with(kLinearMaterial, material));
}

StaticSolution solve(const std::string& json, const std::string& directory = "") {
  const StaticSolution s = solve_static(setup_static_scene(parse_scene(json, "test.json", directory)));
  EXPECT_TRUE(s.converged) << s.message;
  return s;
}

std::string scene_error(const std::string& json, const std::string& directory = "") {
  try {
    setup_static_scene(parse_scene(json, "test.json", directory));
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

double max_difference(const StaticSolution& a, const StaticSolution& b) {
  return (a.displacement - b.displacement).cwiseAbs().maxCoeff();
}

TEST(SplineScene, CorotatedPresetReproducesTheCorotatedMaterial) {
  const StaticSolution reference =
      solve(loaded_box(R"("model": "corotated", "youngs_modulus": 1000, "poisson_ratio": 0.3)"));
  const StaticSolution spline = solve(loaded_box(
      R"("model": "spline", "preset": "corotated", "youngs_modulus": 1000, "poisson_ratio": 0.3)"));
  ASSERT_GT(reference.max_displacement, 0.4);  // ~25% stretch of the 2-long bar: nonlinear
  EXPECT_LT(max_difference(spline, reference), 1e-9 * reference.max_displacement);
  EXPECT_LT((spline.stresses - reference.stresses).cwiseAbs().maxCoeff(), 1e-7 * 250.0);
}

TEST(SplineScene, PlaneStrainCorotatedPreset) {
  const std::string plate = R"({
    "mesh": {"rectangle": {"min": [0, 0], "max": [4, 1], "cells": [8, 2]}},
    "materials": [{"elements": "all", MATERIAL}],
    "dirichlet": [{"vertices": {"plane": {"axis": "x", "value": 0}}}],
    "loads": {"tractions": [{"faces": {"plane": {"axis": "x", "value": 4}}, "traction": [0, -15]}]}
  })";
  const auto scene = [&](const std::string& material) { return with("MATERIAL", material, plate); };
  const StaticSolution reference =
      solve(scene(R"("model": "corotated", "youngs_modulus": 1000, "poisson_ratio": 0.3)"));
  const StaticSolution spline = solve(
      scene(R"("model": "spline", "preset": "corotated", "youngs_modulus": 1000, "poisson_ratio": 0.3)"));
  ASSERT_GT(reference.max_displacement, 0.5);  // a large deflection of the cantilever
  EXPECT_LT(max_difference(spline, reference), 1e-9 * reference.max_displacement);
}

TEST(SplineScene, SmallStrainModuliComeFromExplicitCurves) {
  const LameParameters lame = lame_from_young_poisson(1000.0, 0.3);
  const PrincipalStretchCurves curves = principal_stretch_preset(SplinePreset::neo_hookean, lame);
  testing::TempFolder folder("spline_scene_moduli");
  write_spline_material_file(folder / "material.json", curves, "test");
  const Scene scene = parse_scene(
      with(kLinearMaterial, R"("model": "spline", "curves": {"file": "material.json"}, "density": 2)"),
      "test.json", folder.str());
  ASSERT_TRUE(scene.materials[0].spline_curves);
  EXPECT_NEAR(scene.materials[0].youngs_modulus, 1000.0, 1e-9);
  EXPECT_NEAR(scene.materials[0].poisson_ratio, 0.3, 1e-12);
  EXPECT_EQ(scene.materials[0].density, 2.0);
  // The model's terms pass their derivative checks (energy, gradient, Hessian of the spline term).
  for (const EnergyTermCheck& check : check_static_scene(setup_static_scene(scene)))
    EXPECT_FALSE(check_failed(check)) << check.table();
}

TEST(SplineScene, BadSplineEntriesNameTheirKeyPath) {
  const auto error = [](const std::string& material) { return scene_error(with(kLinearMaterial, material)); };
  EXPECT_EQ(
      error(R"("model": "spline", "youngs_modulus": 1000, "poisson_ratio": 0.3)"),
      "test.json: materials[0]: a spline material needs exactly one of \"preset\" (with youngs_modulus and "
      "poisson_ratio) and \"curves\"");
  EXPECT_EQ(error(R"("model": "spline", "preset": "mooney", "youngs_modulus": 1000, "poisson_ratio": 0.3)")
                .rfind("test.json: materials[0].preset: expected one of", 0),
            0u);
  EXPECT_EQ(error(R"("model": "spline", "preset": "stvk", "poisson_ratio": 0.3)"),
            "test.json: materials[0]: missing required key \"youngs_modulus\"");
  EXPECT_EQ(error(R"("model": "corotated", "preset": "stvk", "youngs_modulus": 1000, "poisson_ratio": 0.3)"),
            "test.json: materials[0].preset: only used by \"model\": \"spline\"");
  const std::string curve = R"({"lower": 0, "upper": 2, "intervals": 2, "controls": [1, 2, 3, 4, 5]})";
  const std::string short_curve = R"({"lower": 0, "upper": 2, "intervals": 2, "controls": [1, 2, 3, 4]})";
  EXPECT_EQ(
      error(R"("model": "spline", "curves": {"uniaxial": )" + curve + R"(, "biaxial": )" + short_curve +
            R"(, "volumetric": )" + curve + "}"),
      "test.json: materials[0].curves.biaxial.controls: expected intervals + 3 = 5 control values, got an "
      "array of 4");
  EXPECT_EQ(error(R"("model": "spline", "curves": {"uniaxial": )" + curve + "}"),
            "test.json: materials[0].curves: missing required key \"biaxial\"");
  EXPECT_EQ(error(R"("model": "spline", "youngs_modulus": 5, "curves": {"file": "m.json"})"),
            "test.json: materials[0].youngs_modulus: not used with explicit curves (the curves carry the "
            "stiffness; use \"preset\" to build curves from E and nu)");
  // Curves without stiffness at rest (all zero) are rejected before Newton sees them.
  const std::string zero = R"({"lower": 0, "upper": 2, "intervals": 2, "controls": [0, 0, 0, 0, 0]})";
  EXPECT_EQ(error(R"("model": "spline", "curves": {"uniaxial": )" + zero + R"(, "biaxial": )" + zero +
                  R"(, "volumetric": )" + zero + "}")
                .rfind("test.json: materials[0].curves: the curves are not stable at rest", 0),
            0u);
  EXPECT_EQ(error(R"("model": "spline", "curves": {"file": "missing.json"})"),
            "test.json: materials[0].curves.file: cannot open file 'missing.json'");
}

TEST(SplineScene, ErrorsInsideACurvesFileNameTheFile) {
  testing::TempFolder folder("spline_scene_file_errors");
  std::ofstream(folder / "bad.json") << R"({"curves": {"uniaxial": {"lower": 0, "upper": 2, "intervals": 2,
    "controls": [1, 2]}, "biaxial": {}, "volumetric": {}}})";
  const std::string message = scene_error(
      with(kLinearMaterial, R"("model": "spline", "curves": {"file": "bad.json"})"), folder.str());
  EXPECT_EQ(message,
            "test.json: materials[0].curves.file: " + (folder / "bad.json") +
                ": curves.uniaxial.controls: expected intervals + 3 = 5 control values, got an array of 2");
}

// Round trip: fit the Neo-Hookean preset from a corotated start (as the shipped
// spline_fit_neo_hookean scene does, on fewer load steps), then use the written material.json
// in a scene: the displacement matches the Neo-Hookean preset's, the fit's own reference.
TEST(SplineScene, FittedMaterialFileDrivesAScene) {
  testing::TempFolder folder("spline_scene_round_trip");
  MaterialFitSpec spec;
  spec.name = "round_trip";
  spec.grids.uniaxial = {0.5, 2.0, 6};
  spec.grids.biaxial = {0.25, 4.0, 6};
  spec.grids.volumetric = {0.1, 3.0, 6};
  spec.cases = {{"tension", LoadCaseKind::uniaxial, {1.1, 1.3, 1.5}},
                {"compression", LoadCaseKind::uniaxial, {0.9, 0.7}},
                {"shear", LoadCaseKind::shear, {0.1, 0.3}},
                {"biaxial", LoadCaseKind::biaxial, {1.1, 1.3}}};
  spec.reference_preset = SplinePreset::neo_hookean;
  spec.reference_lame = lame_from_young_poisson(10.0, 0.3);
  spec.initial_preset = SplinePreset::corotated;
  spec.initial_lame = lame_from_young_poisson(7.0, 0.3);
  spec.smoothness = 1e-4;
  spec.optimizer.backend = OptimizerBackend::ceres_least_squares;
  spec.optimizer.max_iterations = 40;
  const MaterialFitRun run = run_material_fit(spec, folder.str(), nullptr, nullptr);
  ASSERT_LT(*run.relative_stress_error, 1e-5);
  EXPECT_EQ(run.material_path, folder / "material.json");

  const Scene scene =
      parse_scene(with(kLinearMaterial, R"("model": "spline", "curves": {"file": "material.json"})"),
                  "test.json", folder.str());
  EXPECT_EQ(scene.materials[0].spline_curves->controls(), run.result.z);  // written without loss
  // The report holds the same curves (usable as a curves file) and the fields every report has.
  const Scene from_report =
      parse_scene(with(kLinearMaterial, R"("model": "spline", "curves": {"file": "report.json"})"),
                  "test.json", folder.str());
  EXPECT_EQ(from_report.materials[0].spline_curves->controls(), run.result.z);
  std::ifstream report_file(run.report_path);
  const nlohmann::json report = parse_json(report_file);
  EXPECT_EQ(report["report_format"], 1);
  EXPECT_EQ(report["kind"], "material_fit");
  EXPECT_EQ(report["scene"]["name"], "round_trip");
  EXPECT_EQ(report["converged"], run.result.converged());
  EXPECT_EQ(report["material_file"], "material.json");
  for (const char* key : {"tailor_version", "status", "message", "backend", "iterations", "evaluations",
                          "history", "objective", "solves", "timings", "mesh", "load_cases", "curves"})
    EXPECT_TRUE(report.contains(key)) << key;
  for (const char* key : {"total", "setup", "optimization", "forward", "adjoint", "output"})
    EXPECT_TRUE(report["timings"].contains(key)) << key;
  const auto load = [](const std::string& text) {
    return with("\"traction\": [1, 0, 0]", "\"traction\": [1.5, 0.2, 0]", text);
  };
  const StaticSolution fitted = solve(
      load(with(kLinearMaterial, R"("model": "spline", "curves": {"file": "material.json"})")), folder.str());
  const StaticSolution reference = solve(load(
      with(kLinearMaterial,
           R"("model": "spline", "preset": "neo_hookean", "youngs_modulus": 10, "poisson_ratio": 0.3)")));
  ASSERT_GT(reference.max_displacement, 0.2);
  EXPECT_LT(max_difference(fitted, reference), 1e-5 * reference.max_displacement);
}

// The shipped locking bar: corotated up to 1.5x stretch, then the (s - 1.5)_+^3 term of f takes
// over. Uniaxial stress in the bar, P = 2000 = corotated part + 150000 (s - 1.5)^2, gives
// s ~ 1.59 (by hand; the corotated material alone would reach 3x: u = 8 at the tip).
TEST(SplineScene, ShippedLockingBarLocks) {
  const StaticSolution s =
      solve_static(setup_static_scene(read_scene(testing::kScenesDir + "/spline_locking_bar.json")));
  ASSERT_TRUE(s.converged) << s.message;
  EXPECT_GT(s.max_displacement, 4.0 * 0.55);
  EXPECT_LT(s.max_displacement, 4.0 * 0.62);
}

// A spline material inside an inverse scene's forward model: the two-material bar with its stiff
// half made of the Neo-Hookean spline preset; the design (per material) still passes the
// Taylor test, and a scene with no material left to design is refused.
TEST(SplineScene, InverseSceneWithASplineRegionPassesTheTaylorTest) {
  std::ifstream in(testing::kScenesDir + "/two_material_bar_inverse.json");
  std::ostringstream text;
  text << in.rdbuf();
  const std::string spline_half =
      with(R"("model": "neo_hookean", "youngs_modulus": 1e5)",
           R"("model": "spline", "preset": "neo_hookean", "youngs_modulus": 3e5)", text.str());
  testing::TempFolder folder("spline_scene_inverse");
  const GradcheckRun run = gradcheck_scene(parse_scene(spline_half, "bar.json", ""), folder / "out", {});
  EXPECT_TRUE(run.passed()) << run.gradient.table();
  EXPECT_GE(run.gradient.rate1, 1.9) << run.gradient.table();

  const std::string all_spline =
      with(R"("model": "neo_hookean", "youngs_modulus": 3e5)",
           R"("model": "spline", "preset": "neo_hookean", "youngs_modulus": 3e5)", spline_half);
  try {
    build_inverse_problem(parse_scene(all_spline, "bar.json", ""));
    ADD_FAILURE() << "expected a SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("bar.json: inverse.design: every material is a spline material", 0),
              0u)
        << e.what();
  }
}

}  // namespace
}  // namespace tailor::spline_scene_test
