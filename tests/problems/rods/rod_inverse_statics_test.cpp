// Rest-shape design by inverse statics (problems/rods/rod_inverse_statics.hpp, the scene key
// inverse.method): exact recovery of a known rest shape from the equilibrium it produces
// (reference: the truth itself), an unstable equilibrium that the stability check rejects (a
// column standing under its own weight above Greenhill's height, q L^3 / EI > 7.837: the
// straight state is an equilibrium for every rest length, but not a stable one), and the method
// key's refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "../../support/temp_folder.hpp"
#include "forward/solve/newton.hpp"
#include "problems/rods/rod_inverse.hpp"
#include "problems/scene_error.hpp"

namespace tailor::rod_inverse_statics_test {
namespace {

std::string out_dir(const std::string& name) {
  return testing::unique_temp_path("tailor_rod_inverse_statics_" + name).string();
}

// A planar rod of length 1 (20 edges), EI = 1, total weight 2, clamped at its first edge,
// drawn as `points`; gravity along -y, in its plane.
nlohmann::json planar_rod(const nlohmann::json& points) {
  const double r = 1e-2, E = 4.0 / (M_PI * std::pow(r, 4)), g = 9.81, density = 2.0 / (M_PI * r * r * g);
  return {{"rods",
           {{{"name", "strand"},
             {"points", points},
             {"cross_section", {{"radius", r}}},
             {"material", {{"youngs_modulus", E}, {"density", density}}},
             {"clamp", {"first"}}}}},
          {"gravity", {0, -g, 0}},
          {"inverse", {{"design", {"rest_curvature", "rest_length"}}}}};
}

// The truth's rest shape: an S-curve in the xy plane (curvature changing sign along the rod).
nlohmann::json s_curve() {
  nlohmann::json points = nlohmann::json::array();
  double x = 0.0, y = 0.0, angle = 0.0;
  const int n = 21;
  const double h = 1.0 / (n - 1);
  for (int i = 0; i < n; ++i) {
    points.push_back({x, y, 0.0});
    angle += 1.5 * h * std::cos(M_PI * i * h);  // curvature 1.5 cos(pi s)
    x += h * std::cos(angle);
    y += h * std::sin(angle);
  }
  return points;
}

// The truth: the S-curve's own rest strains under point loads; its equilibrium is drawn.
// (Point loads rather than gravity: a scene's weight follows its drawn edge lengths, so the
// truth and the drawn equilibrium would carry weights that differ by the axial strain, 5e-5.)
nlohmann::json loaded_s_curve(const nlohmann::json& points) {
  nlohmann::json scene = planar_rod(points);
  scene["rods"][0]["material"]["density"] = 0.0;
  scene["rods"][0]["point_loads"] = {{{"vertex", 20}, {"force", {0.3, -0.8, 0.0}}},
                                     {{"vertex", 10}, {"force", {-0.2, -0.5, 0.0}}},
                                     {{"vertex", 5}, {"force", {0.0, 0.4, 0.0}}}};
  return scene;
}

TEST(RodInverseStatics, RecoversAKnownRestShapeExactly) {
  const auto truth = build_rod_inverse(loaded_s_curve(s_curve()), "truth", "truth");
  truth->functional->value(truth->z0);
  ASSERT_TRUE(truth->functional->last_newton().converged());
  // On to the round-off floor: the functional's solve stops at 1e-11 of the loads, and the
  // recovery is exact only for an exact equilibrium.
  const Model& model = *truth->model.model;
  const Vector p_truth = truth->functional->parameters();
  Vector y = model.elimination().restrict_state(truth->functional->state());
  NewtonOptions tight;
  tight.relative_tolerance = 1e-16;
  NewtonSolver newton(model, tight);
  const NewtonResult solved = newton.solve(p_truth, y);
  ASSERT_TRUE(solved.converged()) << solved.message;
  const Vector x = model.elimination().expand(y);
  nlohmann::json sagged = nlohmann::json::array();
  for (int v = 0; v < 21; ++v) sagged.push_back({x[3 * v], x[3 * v + 1], x[3 * v + 2]});
  ASSERT_GT(truth->shape_error(x), 0.05);  // the load changes the shape

  nlohmann::json scene = loaded_s_curve(sagged);
  scene["inverse"]["method"] = "inverse_statics";
  const auto problem = build_rod_inverse(scene, "recovery", "recovery");
  const RodInverseStaticsResult s = solve_rod_inverse_statics(*problem);
  const Vector p = problem->parameterization->apply(s.z);
  const RodParameterBlocks& b = problem->model.blocks[0];
  const int ni = 19, ne = 20;
  const double curvature_error =
      (p.segment(b.rest_curvature, 2 * ni) - p_truth.segment(b.rest_curvature, 2 * ni)).lpNorm<Eigen::Infinity>() /
      p_truth.segment(b.rest_curvature, 2 * ni).lpNorm<Eigen::Infinity>();
  const double length_error =
      (p.segment(b.rest_length, ne).array() / p_truth.segment(b.rest_length, ne).array() - 1.0).abs().maxCoeff();
  std::printf(
      "inverse statics: %d steps, residual %.2e -> %.2e (floor %.2e), smallest pivot %.3e, rest-curvature "
      "error %.2e, rest-length error %.2e, %.4f s\n",
      s.steps, s.residual_initial, s.residual, s.stability.residual_floor, s.stability.smallest_pivot,
      curvature_error, length_error, s.seconds);
  EXPECT_TRUE(s.accepted()) << s.message;
  EXPECT_GT(s.stability.smallest_pivot, 0.0);
  EXPECT_LT(curvature_error, 1e-10);
  EXPECT_LT(length_error, 1e-12);

  // Through `tailor run`'s path: the default method picks it, and Newton from the drawn state
  // stays there.
  scene["inverse"].erase("method");
  const auto run_problem = build_rod_inverse(scene, "recovery", "recovery");
  const RodInverseRun run = run_rod_inverse(*run_problem, out_dir("recovery"), nullptr, nullptr);
  EXPECT_EQ(run.method, RodInverseMethod::inverse_statics);
  EXPECT_TRUE(run.result.converged()) << run.result.message;
  EXPECT_TRUE(run.fallback.empty());
  EXPECT_LT(run.shape_error, 1e-12);
  EXPECT_TRUE(run.final_converged);
  EXPECT_TRUE(run.final_stability.stable());
  EXPECT_GT(run.initial_shape_error, 0.01);
}

// A horizontal straight rod under gravity designed by rest curvature alone (no rest lengths):
// the internal force is normal to the rod, so the curvatures alone balance it exactly.
TEST(RodInverseStatics, StraightRodNeedsOnlyRestCurvatures) {
  nlohmann::json points = nlohmann::json::array();
  for (int v = 0; v < 13; ++v) points.push_back({v / 12.0, 0.0, 0.0});
  nlohmann::json scene = planar_rod(points);
  scene["inverse"]["design"] = "rest_curvature";
  const auto problem = build_rod_inverse(scene, "straight", "straight");
  const RodInverseStaticsResult s = solve_rod_inverse_statics(*problem);
  EXPECT_TRUE(s.accepted()) << s.message;
  // The result is the truth's equilibrium condition: the rod now sits as drawn.
  problem->functional->value(s.z);
  EXPECT_LT(problem->shape_error(problem->functional->state()), 1e-12);
}

// A column standing on its clamp (length 1, EI = 1) with a weight of 20, q L^3 / EI = 20 > 7.837
// (Greenhill 1881; Timoshenko & Gere, Theory of Elastic Stability, section 2.14): the straight
// state is an equilibrium at round-off but the free Hessian is indefinite.
nlohmann::json standing_column() {
  nlohmann::json points = nlohmann::json::array();
  for (int v = 0; v < 21; ++v) points.push_back({0.0, v / 20.0, 0.0});
  nlohmann::json scene = planar_rod(points);
  const double r = 1e-2, g = 9.81;
  scene["rods"][0]["material"]["density"] = 20.0 / (M_PI * r * r * g);
  return scene;
}

TEST(RodInverseStatics, UnstableEquilibriumFallsBackToTheOptimizer) {
  const auto problem = build_rod_inverse(standing_column(), "column", "column");
  const RodInverseStaticsResult s = solve_rod_inverse_statics(*problem);
  std::printf("standing column: residual %.2e (floor %.2e), smallest pivot %.3e, %d non-positive\n", s.residual,
              s.stability.residual_floor, s.stability.smallest_pivot, s.stability.nonpositive_pivots);
  EXPECT_TRUE(s.at_round_off) << s.message;
  EXPECT_FALSE(s.stability.stable());
  EXPECT_LT(s.stability.smallest_pivot, 0.0);
  EXPECT_FALSE(s.accepted());

  const RodInverseRun run = run_rod_inverse(*problem, out_dir("column"), nullptr, nullptr);
  EXPECT_EQ(run.method, RodInverseMethod::optimizer);
  EXPECT_NE(run.fallback.find("not stable"), std::string::npos) << run.fallback;
  ASSERT_TRUE(run.statics.has_value());

  // The same column below Greenhill's height (weight 2): accepted.
  nlohmann::json light = standing_column();
  light["rods"][0]["material"]["density"] = 2.0 / (M_PI * 1e-4 * 9.81);
  const auto stable = build_rod_inverse(light, "column", "column");
  EXPECT_TRUE(solve_rod_inverse_statics(*stable).accepted());

  // Asked for explicitly, inverse statics reports the failure instead of falling back.
  nlohmann::json strict = standing_column();
  strict["inverse"]["method"] = "inverse_statics";
  const auto refused = build_rod_inverse(strict, "column", "column");
  const RodInverseRun failed = run_rod_inverse(*refused, out_dir("column_strict"), nullptr, nullptr);
  EXPECT_EQ(failed.method, RodInverseMethod::inverse_statics);
  EXPECT_FALSE(failed.result.converged());
  EXPECT_NE(failed.result.message.find("not stable"), std::string::npos) << failed.result.message;
}

TEST(RodInverseStatics, MethodKeyNamesWhyItDoesNotApply) {
  nlohmann::json scene = planar_rod(s_curve());
  scene["inverse"]["design"] = "radius";
  scene["inverse"]["method"] = "inverse_statics";
  try {
    build_rod_inverse(scene, "bad", "bad");
    ADD_FAILURE() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("inverse.method"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("radius"), std::string::npos) << e.what();
  }
  scene["inverse"]["method"] = "inverse_statistics";
  EXPECT_THROW(build_rod_inverse(scene, "bad", "bad"), SceneError);
  // Not the drawn target: the default method runs the optimizer and says why.
  scene = planar_rod(s_curve());
  scene["inverse"]["design"] = "rest_curvature";
  scene["inverse"]["target"] = {{"vertices", {20}}, {"positions", {{0.9, 0.1, 0.0}}}};
  const auto problem = build_rod_inverse(scene, "target", "target");
  EXPECT_NE(rod_inverse_statics_obstacle(problem->spec, problem->scene).find("target"), std::string::npos);
  scene["inverse"]["method"] = "inverse_statics";
  EXPECT_THROW(build_rod_inverse(scene, "bad", "bad"), SceneError);
}

}  // namespace
}  // namespace tailor::rod_inverse_statics_test
