// The "handles" objective term of inverse scenes: parsing with defaults, u~ as design variables
// after the material design (initialized at ubar, or at the free equilibrium under fbar),
// gradient checks of the shipped handle scenes, the report's per-handle errors, and bad input
// as one SceneError naming the key path.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "../support/temp_folder.hpp"
#include "../support/text_files.hpp"
#include "problems/fem/inverse_commands.hpp"
#include "problems/fem/inverse_handles.hpp"
#include "problems/json_text.hpp"
#include "scene_text.hpp"

namespace tailor::handles_scene_test {
namespace {

using TempFolder = tailor::testing::TempFolder;

// A 2 x 1 x 1 linear box (4 x 2 x 2 cells, E = 1000) clamped at x = 0, without loads; the
// handle on x = 2 pulls with a total force of 30 and should move 0.02 along x.
const std::string kHandles = R"({"type": "handles", "alpha": 0.01, "beta": 1e5,
       "handles": [{"vertices": {"plane": {"axis": "x", "value": 2}}, "force": [30, 0, 0],
                    "displacement": [0.02, 0, 0], "weight": 2}]})";

std::string handle_scene(const std::string& handles = kHandles, const std::string& extra_terms = "",
                         const std::string& optimizer = "") {
  const std::string clamped = R"("dirichlet": [{"vertices": {"plane": {"axis": "x", "value": 0}}}],)";
  std::string text = testing::small_box_scene();
  const auto from = text.find("\"dirichlet\"");
  const auto to = text.find("\"solver\"");
  text.replace(from, to - from, clamped + "\n  ");  // no loads: the handles are the only forces
  return testing::with(
      "\"solver\": {\"load_steps\": 1}",
      "\"solver\": {\"load_steps\": 1},\n  \"inverse\": {\n"
      "    \"design\": {\"parameter\": \"youngs_modulus\", \"granularity\": \"per_material\"},\n"
      "    \"objective\": [" +
          handles + extra_terms + "]" + optimizer + "}",
      text);
}

std::string build_error(const std::string& text) {
  try {
    build_inverse_problem(parse_scene(text, "h.json", ""));
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

using tailor::testing::read_file;
TEST(HandlesScene, ParsesTheTermWithDefaults) {
  const Scene scene = parse_scene(
      handle_scene(
          R"({"type": "handles", "handles": [{"vertices": {"list": [4]}, "force_per_vertex": [1, 0, 0]}]})"),
      "h.json", "");
  const auto* term = find_handles_term(*scene.inverse);
  ASSERT_TRUE(term);
  EXPECT_EQ(term->alpha, 1.0);
  EXPECT_EQ(term->beta, 1.0);
  ASSERT_EQ(term->handles.size(), 1u);
  EXPECT_TRUE(term->handles[0].force_per_vertex);
  EXPECT_FALSE(term->handles[0].displacement);
  EXPECT_EQ(term->handles[0].weight, 1.0);
  EXPECT_EQ(term->handles[0].key, "inverse.objective[0].handles[0]");
}

TEST(HandlesScene, DisplacementsAreDesignVariablesAfterTheMaterialDesign) {
  const auto problem = build_inverse_problem(parse_scene(handle_scene(), "h.json", ""));
  ASSERT_TRUE(problem->handles);
  const int handle_vertices = 9;  // the 3 x 3 vertices of the x = 2 face
  EXPECT_EQ(problem->num_material_design(), 1);
  EXPECT_EQ(problem->num_design(), 1 + 3 * handle_vertices);
  EXPECT_EQ(problem->handles->scale, 0.02);  // |ubar|: the optimizer sees u~ / |ubar|
  for (int k = 0; k < 3 * handle_vertices; ++k)
    EXPECT_EQ(problem->z0[1 + k], k % 3 == 0 ? 1.0 : 0.0);  // ubar
  // J(z0) is the formula: the force misfit at E = 1000 with the handle at ubar.
  const double J = problem->functional->value(problem->z0);
  const Vector p = problem->parameterization->apply(problem->z0);
  const Vector f = problem->handles->objective->total_force(0, problem->functional->state(), p);
  EXPECT_NEAR(J, 0.5 * 0.01 * 2 * (f - Eigen::Vector3d(30, 0, 0)).squaredNorm(), 1e-10 * J);
  // The handle vertices sit where u~ puts them.
  const Vector& x = problem->functional->state();
  for (int v : problem->handles->objective->handle(0).vertices)
    EXPECT_NEAR(x[3 * v] - problem->setup.mesh.rest_positions(v, 0), 0.02, 1e-15);
  // setup_at(z) reproduces the functional's equilibrium with solve_static.
  const StaticSolution solution = solve_static(problem->setup_at(problem->z0));
  ASSERT_TRUE(solution.converged);
  EXPECT_LE((solution.positions - x).norm(), 1e-9 * x.norm());
}

TEST(HandlesScene, WithoutTargetDisplacementStartsFromTheFreeEquilibriumUnderTheForce) {
  // The box clamped at x = 0 with a handle on x = 2 that only asks for a force: u~0 is where
  // that force alone moves the face, so the force term starts at (nearly) zero.
  const auto problem = build_inverse_problem(parse_scene(
      handle_scene(R"({"type": "handles", "handles": [{"vertices": {"plane": {"axis": "x", "value": 2}},
                       "force_per_vertex": [1, 0, 0.5]}]})"),
      "h.json", ""));
  EXPECT_GT(problem->z0.tail(27).cwiseAbs().maxCoeff(), 1e-4);
  const double J = problem->functional->value(problem->z0);
  EXPECT_LT(J, 1e-16);
}

TEST(HandlesScene, ShippedScenesPassTheGradientCheck) {
  TempFolder folder("handles_gradcheck");
  for (const char* name : {"cantilever_handle", "block_core_shell"}) {
    SCOPED_TRACE(name);
    const GradcheckRun run =
        gradcheck_scene(read_scene(testing::kScenesDir + "/" + name + ".json"), folder / name, {});
    EXPECT_TRUE(run.passed()) << run.gradient.table();
    EXPECT_GE(run.gradient.rate1, 1.9) << run.gradient.table();
  }
}

// Neo-Hookean in 3D and plane strain in 2D, with loads on a handle vertex and a handle without
// ubar: the reduced functional of the scene passes its Taylor test.
TEST(HandlesScene, NonlinearAnd2DScenesPassTheGradientCheck) {
  TempFolder folder("handles_gradcheck_nonlinear");
  const std::string neo_hookean =
      testing::with("\"model\": \"linear\"", "\"model\": \"neo_hookean\"",
                    handle_scene(R"({"type": "handles", "alpha": 0.01, "beta": 100, "handles": [
          {"vertices": {"plane": {"axis": "x", "value": 2}}, "force": [30, 5, -10], "displacement": [0.2, 0, -0.1]},
          {"vertices": {"list": [7]}, "force_per_vertex": [0, 0, 3]}]})",
                                 R"(, {"type": "smoothness", "weight": 0.01})"));
  const std::string plate = R"({
  "mesh": {"rectangle": {"min": [0, 0], "max": [2, 1], "cells": [6, 3]}},
  "materials": [{"elements": "all", "model": "neo_hookean", "youngs_modulus": 1000, "poisson_ratio": 0.3}],
  "dirichlet": [{"vertices": {"plane": {"axis": "x", "value": 0}}}],
  "loads": {"nodal": [{"vertices": {"plane": {"axis": "x", "value": 2}}, "force": [0, -5]}]},
  "inverse": {
    "design": {"parameter": "youngs_modulus", "granularity": "per_element"},
    "objective": [{"type": "handles", "alpha": 0.01, "beta": 1e4,
                   "handles": [{"vertices": {"plane": {"axis": "x", "value": 2}}, "force": [0, -40], "displacement": [0, -0.1]}]}]
  }
})";
  for (const auto& [name, text] : {std::pair{"neo_hookean_box", neo_hookean}, std::pair{"plate_2d", plate}}) {
    SCOPED_TRACE(name);
    const GradcheckRun run =
        gradcheck_scene(parse_scene(text, std::string(name) + ".json", ""), folder / name, {});
    EXPECT_TRUE(run.passed()) << run.gradient.table();
    EXPECT_GE(run.gradient.rate1, 1.9) << run.gradient.table();
  }
}

// Material modes and handles together: z = [modal coordinates, u~ / s]; the smooth box keeps E
// in [min, max] and the gradient in both blocks passes the Taylor test.
TEST(HandlesScene, ModalDesignWithHandlesPassesTheGradientCheck) {
  TempFolder folder("handles_gradcheck_modes");
  const std::string text = testing::with(
      R"("granularity": "per_material")", R"("granularity": "modes", "modes": 6, "min": 100, "max": 1e5)",
      testing::with("\"model\": \"linear\"", "\"model\": \"neo_hookean\"", handle_scene()));
  const auto problem = build_inverse_problem(parse_scene(text, "modes_handles.json", ""));
  ASSERT_TRUE(problem->modal.has_value());
  EXPECT_EQ(problem->num_material_design(), 6);
  EXPECT_EQ(problem->num_design(), 6 + problem->handles->size());
  const GradcheckRun run = gradcheck_scene(parse_scene(text, "modes_handles.json", ""), folder / "modes", {});
  EXPECT_TRUE(run.passed()) << run.gradient.table();
  EXPECT_GE(run.gradient.rate1, 1.9) << run.gradient.table();
}

TEST(HandlesScene, RunReportsTheErrorsAtEachHandle) {
  TempFolder folder("handles_run");
  // Force and displacement are consistent for E = 2000 x (stiffness at E = 1000): the optimum
  // meets both. beta = 1e9 >> W k^2 ~ 2 * 500^2 keeps u~ near ubar, so E must change.
  const auto probe = build_inverse_problem(parse_scene(handle_scene(), "h.json", ""));
  probe->functional->value(probe->z0);
  const Vector force_at_1000 = probe->handles->objective->total_force(
      0, probe->functional->state(), probe->parameterization->apply(probe->z0));
  std::ostringstream target;
  target.precision(17);
  target << "[" << 2 * force_at_1000[0] << ", " << 2 * force_at_1000[1] << ", " << 2 * force_at_1000[2]
         << "]";
  const std::string handles =
      testing::with("\"beta\": 1e5", "\"beta\": 1e9", testing::with("[30, 0, 0]", target.str(), kHandles));
  const InverseRun run = run_inverse_scene(
      parse_scene(handle_scene(handles, "", R"(, "optimizer": {"gradient_tolerance": 1e-13})"), "h.json", ""),
      folder / "out");
  ASSERT_TRUE(run.result.converged()) << run.result.report();
  EXPECT_NEAR(run.design_values[0] / 2000.0, 1.0, 1e-4) << run.result.report();
  ASSERT_EQ(run.handles.size(), 1u);
  EXPECT_LT(run.handles[0].relative_force_error, 1e-4);
  EXPECT_LT(run.handles[0].relative_displacement_error, 1e-4);

  const auto report = parse_json(read_file(folder / "out/report.json"));
  EXPECT_EQ(report["design"]["size"], 1);
  const auto& h = report["handles"];
  EXPECT_EQ(h["alpha"], 0.01);
  EXPECT_EQ(h["beta"], 1e9);
  EXPECT_EQ(h["displacement_variables"], 27);
  ASSERT_EQ(h["list"].size(), 1u);
  const auto& first = h["list"][0];
  for (const char* key : {"key", "vertices", "weight", "force", "target_force", "force_per_vertex",
                          "force_error", "relative_force_error", "displacement", "target_displacement",
                          "displacement_error", "relative_displacement_error"})
    EXPECT_TRUE(first.contains(key)) << key;
  EXPECT_EQ(first["key"], "inverse.objective[0].handles[0]");
  EXPECT_EQ(first["vertices"], 9);
  EXPECT_NEAR(first["force"][0].get<double>(), run.handles[0].total_force[0], 1e-12 * force_at_1000[0]);
  EXPECT_EQ(first["relative_displacement_error"].get<double>(), run.handles[0].relative_displacement_error);
  EXPECT_NE(read_file(folder / "out/result.vtu").find("\"handle\""), std::string::npos);
}

TEST(HandlesScene, BadInputNamesTheKeyPath) {
  const std::string handle_on_support =
      R"({"type": "handles", "handles": [{"vertices": {"plane": {"axis": "x", "value": 0}}, "force": [1, 0, 0]}]})";
  const std::string overlapping = R"({"type": "handles", "handles": [
      {"vertices": {"plane": {"axis": "x", "value": 2}}, "force": [1, 0, 0]},
      {"vertices": {"list": [4]}, "force": [1, 0, 0]}]})";
  struct Case {
    std::string text, message;
  };
  const Case cases[] = {
      {handle_scene(R"({"type": "handles", "handles": [{"vertices": {"list": [4]}}]})"),
       "h.json: inverse.objective[0].handles[0]: a handle needs a target: \"displacement\", \"force\" or "
       "\"force_per_vertex\""},
      {handle_scene(
           R"({"type": "handles", "handles": [{"vertices": {"list": [4]}, "force": [1, 0, 0], "force_per_vertex": [1, 0, 0]}]})"),
       "h.json: inverse.objective[0].handles[0].force_per_vertex: give either \"force\""},
      {handle_scene(R"({"type": "handles", "handles": []})"),
       "h.json: inverse.objective[0].handles: expected at least one handle"},
      {handle_scene(
           R"({"type": "handles", "beta": -1, "handles": [{"vertices": {"list": [4]}, "force": [1, 0, 0]}]})"),
       "h.json: inverse.objective[0].beta: expected a number >= 0, got -1"},
      {handle_scene(R"({"type": "handles", "handles": [{"vertices": {"list": [4]}, "force": [1, 0]}]})"),
       "h.json: inverse.objective[0].handles[0].force: expected 3 components (the mesh is 3D), got 2"},
      {handle_scene(kHandles, ",\n" + kHandles),
       "h.json: inverse.objective[1]: at most one \"handles\" term; list every handle in the first one"},
      {handle_scene(handle_on_support),
       "h.json: inverse.objective[0].handles[0].vertices: vertex 0 is also held by a dirichlet condition"},
      {handle_scene(overlapping),
       "h.json: inverse.objective[0].handles[1].vertices: vertex 4 is already in the handle "
       "inverse.objective[0].handles[0]"},
  };
  for (const Case& c : cases) {
    const std::string message = build_error(c.text);
    EXPECT_NE(message.find(c.message), std::string::npos)
        << "got: " << message << "\nexpected: " << c.message;
  }
}

}  // namespace
}  // namespace tailor::handles_scene_test
