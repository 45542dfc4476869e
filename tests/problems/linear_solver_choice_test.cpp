// The scene's "solver.linear_solver" (problems/fem/linear_solver_choice.hpp): parsing, the clear
// error of a program that registered no PETSc back-end (what a build without PETSc is), the
// plumbing of a registered solver into simulate / report.json, the rank-0-only output switch,
// and the vertex coordinates given for algebraic multigrid's rigid-body modes. The registered
// stand-in is Eigen's SimplicialLDLT (not tailor's CHOLMOD path), so the equilibrium it finds
// must match CHOLMOD's to round-off.
#include "problems/fem/linear_solver_choice.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "../support/temp_folder.hpp"
#include "ldlt_stand_in.hpp"
#include "problems/cli/run_cli.hpp"
#include "problems/fem/commands.hpp"
#include "problems/fem/scene.hpp"
#include "problems/fem/static_scene.hpp"
#include "problems/json_text.hpp"
#include "problems/output_process.hpp"
#include "scene_text.hpp"

namespace tailor::linear_solver_choice_test {
namespace {

namespace fs = std::filesystem;
using testing::EigenLdlt;
using testing::last_made;
using testing::RegisteredStandIn;
using testing::with;

const std::string kSolver = "\"solver\": {\"load_steps\": 1}";

std::string scene_error(const std::string& json) {
  try {
    parse_scene(json, "test.json", "");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(LinearSolverChoice, CholmodIsTheDefaultAndNeedsNoSolverObject) {
  EXPECT_EQ(parse_scene(testing::small_box_scene(), "box.json", "").solver.newton.linear_solver, nullptr);
  const Scene scene =
      parse_scene(with(kSolver, "\"solver\": {\"linear_solver\": \"cholmod\"}"), "box.json", "");
  EXPECT_EQ(scene.solver.linear_solver, "cholmod");
  EXPECT_EQ(scene.solver.newton.linear_solver, nullptr);
}

TEST(LinearSolverChoice, PetscWithoutTheBackEndNamesTheBuildOption) {
  ASSERT_FALSE(linear_solver_registered("petsc"));
  const std::string error = scene_error(with(kSolver, "\"solver\": {\"linear_solver\": \"petsc\"}"));
  EXPECT_NE(error.find("test.json: solver.linear_solver: "), std::string::npos) << error;
  EXPECT_NE(error.find("-DTAILOR_WITH_PETSC=ON"), std::string::npos) << error;
}

TEST(LinearSolverChoice, BadKeysAreSceneErrors) {
  EXPECT_NE(scene_error(with(kSolver, "\"solver\": {\"linear_solver\": \"mumps\"}"))
                .find("solver.linear_solver: expected one of cholmod, petsc"),
            std::string::npos);
  EXPECT_NE(scene_error(with(kSolver, "\"solver\": {\"petsc_options\": \"-ksp_type cg\"}"))
                .find("solver.petsc_options: needs \"linear_solver\": \"petsc\""),
            std::string::npos);
  EXPECT_NE(scene_error(with(kSolver, "\"solver\": {\"linear_solver\": \"petsc\", \"petsc_options\": 3}"))
                .find("solver.petsc_options: expected a string of PETSc options"),
            std::string::npos);
  RegisteredStandIn registered;
  // The back-end's rejection of its options, at the options' key.
  EXPECT_NE(
      scene_error(with(kSolver, "\"solver\": {\"linear_solver\": \"petsc\", \"petsc_options\": \"-bad 1\"}"))
          .find("solver.petsc_options: option -bad is unknown"),
      std::string::npos);
}

TEST(LinearSolverChoice, ACommandLineWithoutTheBackEndFailsWithTheBuildOption) {
  testing::TempFolder folder("linear_solver_cli");
  std::ofstream(folder / "box.json") << with(kSolver, "\"solver\": {\"linear_solver\": \"petsc\"}");
  const std::string scene = folder / "box.json", out_dir = folder / "out";
  const char* argv[] = {"tailor", "simulate", scene.c_str(), "--out", out_dir.c_str()};
  std::ostringstream out, err;
  EXPECT_EQ(run_cli(5, argv, out, err), 2);
  EXPECT_NE(err.str().find("TAILOR_WITH_PETSC"), std::string::npos) << err.str();
  EXPECT_FALSE(fs::exists(folder / "out"));
}

TEST(LinearSolverChoice, ARegisteredSolverTakesTheStepsAndIsReported) {
  RegisteredStandIn registered;
  // Whole vertices fixed at x = 0, so the free unknowns are whole vertices.
  const std::string clamped = with("\"components\": [0]}", "\"components\": [0, 1, 2]}");
  const Scene reference_scene = parse_scene(clamped, "box.json", "");
  const Scene scene = parse_scene(
      with(kSolver, "\"solver\": {\"linear_solver\": \"petsc\", \"petsc_options\": \"-ksp_type preonly\"}",
           clamped),
      "box.json", "");
  ASSERT_NE(scene.solver.newton.linear_solver, nullptr);
  testing::TempFolder folder("linear_solver_simulate");
  const SimulateRun reference = simulate_scene(reference_scene, folder / "cholmod");
  const SimulateRun run = simulate_scene(scene, folder / "standin");
  ASSERT_TRUE(run.solution.converged) << run.solution.message;
  EXPECT_GE(last_made()->solves, 1);
  EXPECT_LT((run.solution.positions - reference.solution.positions).norm(),
            1e-10 * reference.solution.positions.norm());

  std::ifstream in(folder / "standin/report.json");
  const auto report = parse_json(in);
  EXPECT_EQ(report["linear_solver"]["name"], "petsc");
  EXPECT_EQ(report["linear_solver"]["options"], "-ksp_type preonly");
  EXPECT_EQ(report["linear_solver"]["krylov_method"], "preonly");
  EXPECT_EQ(report["linear_solver"]["solves"], last_made()->solves);
  std::ifstream in_reference(folder / "cholmod/report.json");
  EXPECT_EQ(parse_json(in_reference)["linear_solver"], nlohmann::json({{"name", "cholmod"}}));

  // The coordinates of the free vertices, 3 per vertex, in the unknowns' order.
  const StaticSetup setup = setup_static_scene(scene);
  const std::unique_ptr<Model> model = build_static_model(setup, 1.0);
  EXPECT_EQ(last_made()->dim, 3);
  EXPECT_EQ(last_made()->coordinates, model->elimination().restrict_state(setup.rest_state()));
}

TEST(LinearSolverChoice, OnlyTheWritingProcessWritesFiles) {
  RegisteredStandIn registered;
  set_writes_output(false);
  testing::TempFolder folder("linear_solver_silent");
  const SimulateRun run =
      simulate_scene(parse_scene(testing::small_box_scene(), "box.json", ""), folder / "out");
  EXPECT_TRUE(run.solution.converged);
  EXPECT_FALSE(fs::exists(folder / "out"));
}

TEST(LinearSolverChoice, VertexCoordinatesOnlyForWholeFreeVertices) {
  // small_box_scene's supports fix single components: no vertex blocks.
  const StaticSetup partial = setup_static_scene(parse_scene(testing::small_box_scene(), "box.json", ""));
  const std::unique_ptr<Model> model = build_static_model(partial, 1.0);
  EXPECT_EQ(free_vertex_coordinates(model->elimination(), 3, partial.rest_state()).size(), 0);
  // Without constraints every vertex is free: the coordinates are the rest state itself.
  const Elimination none = Elimination::identity(static_cast<int>(partial.rest_state().size()));
  EXPECT_EQ(free_vertex_coordinates(none, 3, partial.rest_state()), partial.rest_state());
  EXPECT_EQ(free_vertex_coordinates(none, 2, partial.rest_state()).size(), 0);  // 3 * 45 is not even
}

}  // namespace
}  // namespace tailor::linear_solver_choice_test
