// Static rod scenes (problems/rods/rod_scene.cpp, solve_rod_model): twisting moments as one
// potential of the state, the report's own check that a converged run's residual is what its
// load steps converged to, and free rods refused before solving.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../../support/temp_folder.hpp"
#include "forward/rods/discrete_rod.hpp"
#include "problems/fem/scene.hpp"
#include "problems/json_text.hpp"
#include "problems/rods/rod_scene.hpp"
#include "rod_scene_files.hpp"

namespace tailor::rod_scene_statics_test {
namespace {

nlohmann::json read_report(const RodSimulation& sim) {
  std::ifstream in(sim.report_path);
  return parse_json(in);
}

// A straight rod of length 1, 20 edges, circular section r = 0.01 with GJ = 1 (G given, so
// G J = 1 exactly with J = pi r^4 / 2), clamped at its first edge, twisted by M at its last.
nlohmann::json twisted_rod(double M, int load_steps) {
  const double r = 0.01, J = M_PI * std::pow(r, 4) / 2.0, G = 1.0 / J;
  nlohmann::json scene = {
      {"rods",
       {{{"name", "bar"},
         {"line", {{"from", {0, 0, 0}}, {"to", {1, 0, 0}}, {"vertices", 21}}},
         {"cross_section", {{"shape", "circle"}, {"radius", r}}},
         {"material", {{"youngs_modulus", 2.6 * G}, {"shear_modulus", G}}},
         {"clamp", {"first"}},
         {"twisting_moments", {{{"edge", 19}, {"moment", M}}}}}}},
      {"load_steps", load_steps}};
  return scene;
}

// Saint-Venant torsion: a uniform twist, the end section turned by theta = M L / (G J).
// L is the length between the clamp and the loaded section: with the staggered clamp of
// docs/rods.md (the clamped edge's midpoint is the clamp, loads act at the last edge's
// midpoint) L = (edges - 1) h = 0.95, and the discrete twist is uniform, so the formula holds
// to round-off (with the rod's full length 1 it would be off by h / L = 5 %, the first-order
// error of a clamp placed at a vertex). Independent of the number of load steps.
TEST(RodSceneStatics, EndMomentTwistsAStraightRodBySaintVenant) {
  const double M = 0.5, GJ = 1.0, L = 19 * 0.05;
  const double reference = M * L / GJ;
  double first = 0.0;
  for (int steps : {1, 4, 16}) {
    const RodSceneSpec spec = parse_rod_scene(twisted_rod(M, steps));
    const auto dir = testing::unique_temp_path("tailor_rod_twist");
    const RodSimulation sim = simulate_rods(spec, dir.string());
    ASSERT_TRUE(sim.converged);
    const int twists = 3 * 21;
    const double theta = sim.state[twists + 19] - sim.state[twists + 0];
    std::printf("load steps %2d: end twist %.12f, M L / GJ %.12f\n", steps, theta, reference);
    EXPECT_NEAR(theta, reference, 1e-9 * reference);
    if (steps == 1) first = theta;
    EXPECT_NEAR(theta, first, 1e-10 * reference);
    const nlohmann::json report = read_report(sim);
    EXPECT_EQ(report["status"], "converged");
    EXPECT_EQ(report["energies"].count("rod_twisting_moments"), 1u);
    std::filesystem::remove_all(dir);
  }
}

double tip_z(const RodSimulation& sim) { return sim.state[3 * 40 + 2]; }

// The shipped cantilever (gravity, a tip load and a twisting moment on the last edge of an
// elliptic section): the tip is the same for 1, 4 and 16 load steps, and the report's residual
// (the free gradient at the result, after the frames' last update) is the last step's. Before,
// the moment was a force on theta, whose meaning changed with each frame update: tip z
// 8.73e-5, 1.308e-4, 1.417e-4 for 1, 4, 16 steps, all "converged" with report residuals 0.132,
// 0.033, 0.0083 (each step's own final residual 5e-8). Reference: the 1-step solve, in which
// no frame moves (so the moment there is -M theta, unchanged by the fix).
TEST(RodSceneStatics, ShippedCantileverTipDoesNotDependOnLoadSteps) {
  nlohmann::json scene = testing::read_rod_scene("rod_cantilever.json");
  double reference = 0.0;
  for (int steps : {1, 4, 16}) {
    scene["load_steps"] = steps;
    const RodSceneSpec spec = parse_rod_scene(scene);
    const auto dir = testing::unique_temp_path("tailor_rod_cantilever");
    const RodSimulation sim = simulate_rods(spec, dir.string());
    ASSERT_TRUE(sim.converged);
    const nlohmann::json report = read_report(sim);
    const double residual = report["residual"], start = report["steps"][0]["initial_residual"];
    std::printf("load steps %2d: tip z %.10e, report residual %.3e (first step's initial %.3e)\n", steps,
                tip_z(sim), residual, start);
    EXPECT_EQ(report["status"], "converged");
    EXPECT_LT(residual, 1e-6 * start);
    if (steps == 1) reference = tip_z(sim);
    EXPECT_NEAR(tip_z(sim), reference, 1e-6 * std::abs(reference));
    std::filesystem::remove_all(dir);
  }
  EXPECT_NEAR(reference, 8.7265e-5, 1e-8);
}

// The old moment, -M theta on the twist DOF (a function of the stored frames): Newton
// converges on it, but the residual at the result after the frames' update is 0.13. The
// report must not say converged.
class ForceOnTheta final : public EnergyTerm {
 public:
  ForceOnTheta(int dof, double moment) : dof_(dof), moment_(moment) {}
  std::string name() const override { return "force_on_theta"; }
  void evaluate(const Vector& x, const Vector&, const EnergyRequest& request) const override {
    if (request.value) *request.value -= moment_ * x[dof_];
    if (request.gradient) (*request.gradient)[dof_] -= moment_;
  }

 private:
  int dof_;
  double moment_;
};

TEST(RodSceneStatics, ConvergedRunWhoseResidualDisagreesIsReportedNotConverged) {
  nlohmann::json scene = testing::read_rod_scene("rod_cantilever.json");
  scene["rods"][0].erase("twisting_moments");
  scene["load_steps"] = 1;
  const RodSceneSpec spec = parse_rod_scene(scene);
  RodSceneModel m = build_rod_model(spec);
  m.model->add(std::make_unique<ForceOnTheta>(m.rods[0]->twist_dof(39), 0.5));
  const auto dir = testing::unique_temp_path("tailor_rod_inconsistent");
  const RodSimulation sim = solve_rod_model(m, spec, dir.string());
  EXPECT_FALSE(sim.converged);
  const nlohmann::json report = read_report(sim);
  EXPECT_EQ(report["status"], "not_converged");
  EXPECT_TRUE(report["steps"][0]["converged"].get<bool>());  // the step itself did converge
  const std::string message = report["message"];
  EXPECT_NE(message.find("the residual at the result"), std::string::npos) << message;
  EXPECT_GT(report["residual"].get<double>(), 0.1);
  std::filesystem::remove_all(dir);
}

std::string error_of(const nlohmann::json& scene, const std::string& source) {
  RodSceneSpec spec = parse_rod_scene(scene);
  spec.source = source;
  const auto dir = testing::unique_temp_path("tailor_rod_free");
  try {
    simulate_rods(spec, dir.string());
  } catch (const SceneError& e) {
    std::filesystem::remove_all(dir);
    return e.what();
  }
  std::filesystem::remove_all(dir);
  return "no error";
}

// A rod without supports has no static equilibrium: before, Newton ran its 200 iterations
// with a growing residual (the rod falling under gravity); now the scene is refused before
// solving, naming the file, the rod and the free motions. A rod pinned at one vertex keeps
// its three rotations about the pin; two rods joined by a pinned joint are held when one of
// them is clamped (the shipped frame) and free together when neither is.
TEST(RodSceneStatics, FreeRodsAreRefusedNamingTheFreeMotions) {
  nlohmann::json scene = testing::read_rod_scene("rod_cantilever.json");
  scene["rods"][0].erase("clamp");
  const auto t0 = std::chrono::steady_clock::now();
  const std::string free = error_of(scene, "free_rod.json");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 2.0);
  EXPECT_NE(free.find("free_rod.json: rods[0] (\"beam\"): the supports leave the rod free to move rigidly "
                      "(translation along (1, 0, 0); translation along (0, 1, 0); translation along (0, 0, 1); "
                      "rotation about"),
            std::string::npos)
      << free;
  EXPECT_NE(free.find("no equilibrium"), std::string::npos) << free;
  scene["rods"][0]["pin"] = {20};
  const std::string pinned = error_of(scene, "pinned_rod.json");
  EXPECT_NE(pinned.find("rotation about (1, 0, 0) through (0.5, 0, 0)"), std::string::npos) << pinned;
  EXPECT_EQ(pinned.find("translation"), std::string::npos) << pinned;

  nlohmann::json frame = testing::read_rod_scene("rod_frame.json");
  EXPECT_EQ(error_of(frame, "rod_frame.json"), "no error");
  frame["rods"][0].erase("clamp");
  frame["rods"][1].erase("clamp");
  const std::string joined = error_of(frame, "loose_frame.json");
  EXPECT_NE(joined.find("loose_frame.json: rods[0] (\"left\") and rods[1] (\"right\"), joined: the supports leave "
                        "them free to move rigidly"),
            std::string::npos)
      << joined;
}

}  // namespace
}  // namespace tailor::rod_scene_statics_test
