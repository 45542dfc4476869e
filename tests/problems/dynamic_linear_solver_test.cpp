// Dynamic scenes on solver.linear_solver (docs/petsc.md), without MPI: the registered stand-in
// (Eigen's LDL^T, tests/problems/ldlt_stand_in.hpp) takes every step's Newton solve and the
// transient adjoint's backward solves, and the trajectory and the whole gradient match
// CHOLMOD's path (TimeIntegrator with NewtonSolver's kept factors; TransientFunctional's
// CG preconditioned by old factors) to their tolerances. The adjoint solves are asked for
// TransientFunctionalOptions::linear_relative_tolerance, and gradcheck.json records it.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "../support/temp_folder.hpp"
#include "adjoint/transient_functional.hpp"
#include "ldlt_stand_in.hpp"
#include "problems/fem/dynamic_commands.hpp"
#include "problems/fem/dynamic_scene.hpp"
#include "problems/json_text.hpp"
#include "scene_text.hpp"

namespace tailor::dynamic_linear_solver_test {
namespace {

using namespace tailor::testing;

const std::string kDynamics =
    R"({"scheme": "newmark", "time_step": 0.05, "steps": 6, "rayleigh": {"alpha": 0.5, "beta": 0.01},
        "objective": {"vertices": {"plane": {"axis": "x", "value": 2}}, "steps": [3, 6], "target": [0.01, 0, 0]}})";

// small_box_scene with a density and `solver` added to its solver section; `model` "linear"
// (constant step Hessians: CHOLMOD's path solves them with Newton's kept factor) or
// "neo_hookean" (CHOLMOD's adjoint: CG preconditioned by an older step's factor).
std::string dynamic_box(const std::string& solver, const std::string& model = "linear") {
  const std::string text =
      with(R"("model": "linear", "youngs_modulus": 1000, "poisson_ratio": 0.3})",
           R"("model": ")" + model + R"(", "youngs_modulus": 1000, "poisson_ratio": 0.3, "density": 1})");
  return with(R"("solver": {"load_steps": 1})",
              R"("solver": {"load_steps": 1)" + solver + "}, \"dynamics\": " + kDynamics, text);
}

// The trajectory's last state and the gradient of the scene's objective in (log E, log rho,
// alpha, beta), as gradcheck_dynamic_scene designs them, at the scene's values.
struct Transient {
  Vector x, v, gradient;
  double value = 0.0;
  TransientStatistics statistics;
};

Transient evaluate(const Scene& scene) {
  DynamicSceneModel d = build_dynamic_scene(scene);
  const int m = d.setup.mesh.num_elements();
  TimeIntegrator integrator(*d.model, d.options);
  DynamicState state = integrator.initial_state(d.initial_positions, d.initial_velocities, d.p);
  for (int n = 0; n < scene.dynamics->steps; ++n) {
    const NewtonResult r = integrator.step(state, d.p);
    EXPECT_TRUE(r.converged()) << r.message;
  }
  Transient t{state.x, state.v, {}, 0.0, {}};
  const TrajectoryTargetSpec& target = *scene.dynamics->objective;
  std::vector<Keyframe> frames;
  const std::vector<int> vertices = {static_cast<int>(d.setup.mesh.num_vertices()) - 1};
  for (int step : target.steps) frames.push_back({step, Matrix::Constant(1, 3, 0.01), 1.0});
  auto objective = std::make_shared<KeyframeTargets>(3, vertices, target.quantity, frames);
  const ParameterizationPtr map = embed_blocks(
      d.p, {{0, exp_map(m)}, {d.terms.density_offset, exp_map(m)}, {d.terms.alpha_offset, identity_map(2)}});
  Vector z(map->num_design());
  z.head(m) = d.p.head(m).array().log().matrix();
  z.segment(m, m) = d.p.segment(d.terms.density_offset, m).array().log().matrix();
  z.tail(2) << d.p[d.terms.alpha_offset], d.p[d.terms.beta_offset];
  TransientFunctionalOptions options;
  options.steps = scene.dynamics->steps;
  TransientFunctional functional(integrator, map, objective, d.initial_positions, d.initial_velocities,
                                 options);
  t.value = functional.value_and_gradient(z, t.gradient);
  t.statistics = functional.statistics();
  return t;
}

class DynamicLinearSolverModels : public ::testing::TestWithParam<std::string> {};

TEST_P(DynamicLinearSolverModels, StepsAndTheTransientAdjointGoThroughTheRegisteredSolver) {
  RegisteredStandIn registered;
  const Scene reference_scene = parse_scene(dynamic_box("", GetParam()), "box.json", "");
  const Scene scene = parse_scene(dynamic_box(R"(, "linear_solver": "petsc")", GetParam()), "box.json", "");
  ASSERT_NE(scene.solver.newton.linear_solver, nullptr);
  const Transient reference = evaluate(reference_scene);
  const int solves_before = last_made()->solves;
  const Transient run = evaluate(scene);
  ASSERT_GT(last_made()->solves, solves_before);
  // Steps solved to Newton's 1e-10 on both paths, adjoints to 1e-12.
  EXPECT_LT((run.x - reference.x).norm(), 1e-10 * reference.x.norm());
  EXPECT_LT((run.v - reference.v).norm(), 1e-8 * reference.v.norm());
  EXPECT_NEAR(run.value, reference.value, 1e-12 * std::abs(reference.value));
  EXPECT_LT((run.gradient - reference.gradient).norm(), 1e-8 * reference.gradient.norm());
  // One backward solve per step on the stand-in, at the adjoint's tolerance; none on CHOLMOD's.
  EXPECT_EQ(run.statistics.linear_solver_solves, scene.dynamics->steps);
  EXPECT_EQ(run.statistics.factorizations, 0);
  EXPECT_EQ(run.statistics.last_linear_solve.relative_tolerance,
            TransientFunctionalOptions{}.linear_relative_tolerance);
  const std::vector<double>& asked = last_made()->tolerances;
  ASSERT_GE(asked.size(), 6u);
  for (std::size_t i = asked.size() - 6; i < asked.size(); ++i) EXPECT_EQ(asked[i], 1e-12);
  EXPECT_EQ(reference.statistics.linear_solver_solves, 0);
  EXPECT_GT(reference.statistics.factorizations + reference.statistics.cg_solves +
                reference.statistics.kept_factor_solves,
            0);
}

INSTANTIATE_TEST_SUITE_P(DynamicLinearSolver, DynamicLinearSolverModels,
                         ::testing::Values("linear", "neo_hookean"));

TEST(DynamicLinearSolver, ReportsRecordTheSolverAndTheAdjointTolerance) {
  RegisteredStandIn registered;
  const Scene scene =
      parse_scene(dynamic_box(R"(, "linear_solver": "petsc", "petsc_options": "-x 1")"), "box.json", "");
  TempFolder folder("dynamic_linear_solver");
  const DynamicRun simulated = simulate_dynamic_scene(scene, folder / "simulate", nullptr);
  ASSERT_TRUE(simulated.completed) << simulated.message;
  std::ifstream report_file(simulated.report_path);
  const auto report = parse_json(report_file);
  EXPECT_EQ(report["linear_solver"]["name"], "petsc");
  EXPECT_EQ(report["linear_solver"]["options"], "-x 1");

  const GradcheckRun checked = gradcheck_dynamic_scene(scene, folder / "gradcheck", 1, nullptr);
  EXPECT_TRUE(checked.passed()) << checked.gradient.table();
  std::ifstream gradcheck_file(checked.report_path);
  const auto gradcheck = parse_json(gradcheck_file);
  EXPECT_EQ(gradcheck["linear_solver"]["name"], "petsc");
  EXPECT_EQ(gradcheck["adjoint_linear_solves"]["relative_tolerance"], 1e-12);
  EXPECT_EQ(gradcheck["adjoint_linear_solves"]["solves"], 6);

  // The CHOLMOD default writes no adjoint_linear_solves, and its report names cholmod.
  const Scene reference = parse_scene(dynamic_box(""), "box.json", "");
  const GradcheckRun plain = gradcheck_dynamic_scene(reference, folder / "plain", 1, nullptr);
  std::ifstream plain_file(plain.report_path);
  const auto plain_json = parse_json(plain_file);
  EXPECT_FALSE(plain_json.contains("adjoint_linear_solves"));
  EXPECT_EQ(plain_json["linear_solver"], nlohmann::json({{"name", "cholmod"}}));
}

TEST(DynamicLinearSolver, OnlyTheWritingProcessWritesFrames) {
  RegisteredStandIn registered;
  set_writes_output(false);
  const Scene scene = parse_scene(dynamic_box(R"(, "linear_solver": "petsc")"), "box.json", "");
  TempFolder folder("dynamic_linear_solver_silent");
  const DynamicRun run = simulate_dynamic_scene(scene, folder / "out", nullptr);
  EXPECT_TRUE(run.completed) << run.message;
  EXPECT_FALSE(std::filesystem::exists(folder / "out"));
  const GradcheckRun checked = gradcheck_dynamic_scene(scene, folder / "gradcheck", 1, nullptr);
  EXPECT_TRUE(checked.passed()) << checked.gradient.table();
  EXPECT_FALSE(std::filesystem::exists(folder / "gradcheck"));
}

}  // namespace
}  // namespace tailor::dynamic_linear_solver_test
