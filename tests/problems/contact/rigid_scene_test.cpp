// Rigid-body contact scenes: the shipped scenes solve to equilibrium (reference: statics, the
// contact force on each body equals its weight plus what rests on it), and bad input gets a
// SceneError naming the file and the JSON path.
#include "problems/contact/rigid_scene.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../../support/report_checks.hpp"
#include "../../support/temp_folder.hpp"
#include "problems/fem/scene.hpp"
#include "problems/json_text.hpp"
#include "problems/scene_kinds.hpp"
#include "problems/scene_node.hpp"
#include "tests/support/test_paths.hpp"

namespace tailor::rigid_scene_test {
namespace {

const std::string kScenes = std::string(::tailor::testing::test_data_dir()) + "/../../scenes/contact/";

std::string temporary_directory(const std::string& name) {
  const auto dir = testing::unique_temp_path("tailor_contact_" + name);
  std::filesystem::remove_all(dir);
  return dir.string();
}

// The scene file as `tailor simulate` reads it (named after its file without a "name").
RigidSceneSpec read_rigid_scene(const std::string& path) {
  const SceneFile file = read_scene_file(path);
  RigidSceneSpec spec = parse_rigid_scene(file.node(), file.directory());
  spec.name = file.name();
  return spec;
}

// A scene given as text, as read from a file named `source`.
RigidSceneSpec parse_rigid_text(const std::string& text, const std::string& source) {
  const SceneFile file = scene_from_text(text, source);
  return parse_rigid_scene(file.node(), "");
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(RigidScene, SphereOnBoxCarriesTheWeightsDownToTheGround) {
  const RigidSceneSpec spec = read_rigid_scene(kScenes + "sphere_on_box.json");
  ASSERT_EQ(spec.bodies.size(), 3u);
  const std::string out = temporary_directory("sphere_on_box");
  const RigidSimulateRun run = simulate_rigid_scene(spec, out, nullptr);
  ASSERT_TRUE(run.newton.converged()) << run.newton.report();
  const double g = 9.81, box = spec.bodies[1].mass, sphere = spec.bodies[2].mass;
  EXPECT_NEAR(run.contact_forces[6 * 2 + 2], sphere * g, 1e-7 * sphere * g);           // sphere: its weight
  EXPECT_NEAR(run.contact_forces[6 * 1 + 2], box * g, 1e-7 * box * g);                 // box: net of sphere
  EXPECT_NEAR(run.contact_forces[2], -(box + sphere) * g, 1e-7 * (box + sphere) * g);  // ground: both
  EXPECT_GT(run.min_distance, 0.0);
  std::ifstream in(out + "/report.json");
  const nlohmann::json report = parse_json(in);
  testing::expect_report_header(out + "/report.json");
  EXPECT_EQ(report["status"], "converged");
  EXPECT_EQ(report["bodies"].size(), 3u);
  for (const char* body : {"ground", "box", "sphere"})
    EXPECT_TRUE(std::filesystem::exists(out + "/" + body + ".vtu"));
}

TEST(RigidScene, BoxOnGroundConverges) {
  const RigidSimulateRun run = simulate_rigid_scene(read_rigid_scene(kScenes + "box_on_ground.json"),
                                                    temporary_directory("box"), nullptr);
  EXPECT_TRUE(run.newton.converged()) << run.newton.report();
  EXPECT_NEAR(run.contact_forces[8], 7800.0 * 9.81, 1e-6 * 7800.0 * 9.81);
}

// tailor gradcheck on a rigid scene: the adjoint gradient with respect to the masses through
// the stacked contact equilibrium passes the Taylor test (rates ~1 without, ~2 with it).
TEST(RigidScene, GradcheckThroughStackedContactPasses) {
  const TaylorTestResult t = gradcheck_rigid_scene(read_rigid_scene(kScenes + "sphere_on_box.json"),
                                                   temporary_directory("gc"), 1, nullptr);
  EXPECT_TRUE(t.passed()) << t.table();
  EXPECT_GE(t.rate1, 1.9);
  EXPECT_NEAR(t.rate0, 1.0, 0.1);
}

// A dynamic scene: every implicit Euler step converges, no step leaves an intersection, and
// the box ends at rest on the ground carrying its weight.
TEST(RigidScene, DroppedBoxSceneCompletesWithoutIntersections) {
  const RigidSceneSpec spec = read_rigid_scene(kScenes + "box_drop.json");
  const std::string out = temporary_directory("drop");
  const RigidSimulateRun run = simulate_rigid_scene(spec, out, nullptr);
  EXPECT_TRUE(run.completed());
  EXPECT_EQ(run.steps_completed, spec.steps);
  EXPECT_EQ(run.intersections, 0);
  EXPECT_GT(run.min_distance, 0.0);
  const double weight = spec.bodies[1].mass * 9.81;
  EXPECT_NEAR(run.contact_forces[8], weight, 1e-3 * weight);
  EXPECT_TRUE(std::filesystem::exists(out + "/box_0100.vtu"));
  EXPECT_THROW(gradcheck_rigid_scene(spec, out, 1, nullptr), SceneError);
}

// Friction in a scene: the box slides down the 30 degree incline with Coulomb's acceleration
// a = g (sin 30 - mu cos 30) (mu = 0.5): its velocity grows by 0.5 s x a between steps 50 and
// 100. The report gives kappa (adaptive, within its bounds) and the friction settings.
TEST(RigidScene, BoxSlidesDownTheInclineWithCoulombFriction) {
  RigidSceneSpec spec = read_rigid_scene(kScenes + "box_on_incline.json");
  const std::string out = temporary_directory("incline");
  const RigidSimulateRun run = simulate_rigid_scene(spec, out, nullptr);
  ASSERT_TRUE(run.completed()) << run.newton.report();
  EXPECT_EQ(run.intersections, 0);
  spec.steps = 50;
  const RigidSimulateRun half = simulate_rigid_scene(spec, temporary_directory("incline_half"), nullptr);
  ASSERT_TRUE(half.completed()) << half.newton.report();
  const double theta = M_PI / 6, a = 9.81 * (std::sin(theta) - 0.5 * std::cos(theta));
  const Eigen::Vector3d down(std::cos(theta), 0, -std::sin(theta));
  const double measured = (run.velocities[1] - half.velocities[1]).dot(down) / 0.5;
  std::printf("incline scene: acceleration %.6f m/s^2, Coulomb %.6f m/s^2\n", measured, a);
  EXPECT_NEAR(measured, a, 1e-2 * a);  // the box still rocks a little from its landing
  std::ifstream in(out + "/report.json");
  const nlohmann::json report = parse_json(in);
  EXPECT_EQ(report["stiffness"]["mode"], "adaptive");
  const double kappa = report["stiffness"]["final"];
  EXPECT_GE(kappa, report["stiffness"]["min"].get<double>());
  EXPECT_LE(kappa, report["stiffness"]["max"].get<double>());
  EXPECT_EQ(report["friction"]["coefficient"], 0.5);
  EXPECT_GT(report["per_step"][99]["sliding_pairs"].get<int>(), 0);
}

// A kinematic plate pushes a box (it keeps its prescribed pose exactly, the box moves with it);
// a torque turns another box about the vertical against friction.
TEST(RigidScene, KinematicPlateAndTorqueScene) {
  const RigidSceneSpec spec = read_rigid_scene(kScenes + "plate_pushes_box.json");
  const RigidSimulateRun run = simulate_rigid_scene(spec, temporary_directory("plate"), nullptr);
  ASSERT_TRUE(run.completed()) << run.newton.report();
  EXPECT_EQ(run.intersections, 0);
  EXPECT_NEAR(run.state[12], -0.32 + 0.5 * 1.0, 1e-12);  // the plate at x0 + v t
  EXPECT_GT(run.state[6], 0.1);                          // the box went along
  EXPECT_GT(std::abs(run.state[23]), 0.3);               // the turned box turned about z
}

// A static scene without any support: the shipped sphere-on-box scene less its fixed ground
// (a free sphere resting on a free box). Contact resists only relative motion, so both fall
// together: no equilibrium. Before, Newton's first (singular, ~1e18 long) direction made CCD
// iterate for minutes in the first line search; now the scene is refused before solving (the
// SceneError comes from the check, not from a solve), naming the file and the free motion, for simulate and gradcheck alike.
TEST(RigidScene, SceneWithoutSupportIsRefusedAtOnceNamingTheFreeMotion) {
  nlohmann::json scene = parse_json(read_text(kScenes + "sphere_on_box.json"));
  nlohmann::json bodies = nlohmann::json::array();
  for (const auto& body : scene["rigid_bodies"])
    if (body["name"] != "ground") bodies.push_back(body);
  scene["rigid_bodies"] = bodies;
  const RigidSceneSpec spec = parse_rigid_text(dump_json(scene), "free_sphere_on_box.json");
  for (int verb = 0; verb < 2; ++verb) {
    try {
      if (verb == 0)
        simulate_rigid_scene(spec, temporary_directory("free"), nullptr);
      else
        gradcheck_rigid_scene(spec, temporary_directory("free_gc"), 1, nullptr);
      ADD_FAILURE() << "a scene without support was solved";
    } catch (const SceneError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("free_sphere_on_box.json: the bodies are free to move together as one rigid body "
                          "(translation along (0, 0, 1))"),
                std::string::npos)
          << what;
      EXPECT_NE(what.find("no equilibrium"), std::string::npos) << what;
    }
  }
  // A single free box: free in z and in the two tilts (it may not turn about z: held).
  scene["rigid_bodies"] = nlohmann::json::array({bodies[0]});
  try {
    simulate_rigid_scene(parse_rigid_text(dump_json(scene), "free_box.json"), temporary_directory("box1"),
                         nullptr);
    ADD_FAILURE() << "a free box was solved";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("free_box.json: the body \"box\" is free to move rigidly (translation "
                                         "along (0, 0, 1); rotation about"),
              std::string::npos)
        << e.what();
  }
  // The same bodies in dynamics are fine (they fall): no refusal there.
  scene["rigid_bodies"] = bodies;
  scene["dynamics"] = {{"time_step", 0.01}, {"steps", 2}};
  const RigidSimulateRun run =
      simulate_rigid_scene(parse_rigid_text(dump_json(scene), "falling.json"), temporary_directory("fall"), nullptr);
  EXPECT_TRUE(run.completed()) << run.newton.report();
}

// A rigid box dropped with a time step of 1000 s (inertia ~1e-6 of the statics: lateral
// motion and spin nearly free). Newton fails after its 100 iterations; before, the line
// searches of a ~1e18 long direction spent 25 s in CCD (one 55 s on a loaded machine) and the
// report said 0 Newton iterations (a failed step's iterations were not counted). Now CCD's
// work per line search is bounded and the report counts every iteration that ran.
TEST(RigidScene, HugeTimeStepFailsAtItsIterationLimitAndCountsThem) {
  nlohmann::json scene = parse_json(read_text(kScenes + "box_drop.json"));
  scene["dynamics"]["time_step"] = 1000.0;
  scene["dynamics"]["steps"] = 2;
  const RigidSceneSpec spec = parse_rigid_text(dump_json(scene), "box_h1000.json");
  const std::string out = temporary_directory("h1000");
  const auto t0 = std::chrono::steady_clock::now();
  const RigidSimulateRun run = simulate_rigid_scene(spec, out, nullptr);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  double line_search = 0.0, slowest = 0.0;
  for (const NewtonIteration& it : run.newton.history) {
    line_search += it.line_search_seconds;
    slowest = std::max(slowest, it.line_search_seconds);
  }
  std::printf("h = 1000: %s after %d iterations, %.3f s (line searches %.3f s, slowest %.4f s)\n",
              to_string(run.newton.status).c_str(), run.newton.iterations, seconds, line_search, slowest);
  // Bounded work, not wall time (the sanitizer build runs 100 times slower): the step fails at
  // the iteration limit, each iteration with one line search.
  EXPECT_FALSE(run.completed());
  EXPECT_EQ(run.newton.status, NewtonStatus::max_iterations);
  EXPECT_EQ(run.newton.iterations, 100);
  EXPECT_EQ(run.newton.history.size(), 100u);
  std::ifstream in(out + "/report.json");
  const nlohmann::json report = parse_json(in);
  EXPECT_EQ(report["status"], "failed");
  EXPECT_EQ(report["steps_completed"], 0);
  EXPECT_EQ(report["newton_iterations"].get<int>(), run.newton.iterations);
  EXPECT_GT(report["newton_iterations"].get<int>(), 0);
}

void expect_scene_error(const std::string& json, const std::string& fragment) {
  try {
    const RigidSceneSpec spec = parse_rigid_scene(scene_from_text(json, "bad.json").node(), "");
    simulate_rigid_scene(spec, temporary_directory("bad"), nullptr);
    ADD_FAILURE() << "no error for " << json;
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(RigidScene, BadInputIsReportedWithContext) {
  const std::string ground =
      R"({"primitive": "box", "size": [4, 4, 1], "position": [0, 0, -0.5], "fixed": true})";
  expect_scene_error(R"({"rigid_bodies": []})", "at least one body");
  expect_scene_error(R"({"rigid_bodies": [{"primitive": "cone"}]})", "rigid_bodies[0]");
  expect_scene_error(R"({"rigid_bodies": [{"primitive": "box", "size": [1, 1]}]})", "size");
  expect_scene_error(R"({"rigid_bodies": [{"primitive": "box", "size": [1, 1, 1], "colour": 1}]})", "colour");
  expect_scene_error(R"({"rigid_bodies": [)" + ground + R"(], "contact": {"friction": 0.3}})",
                     "friction needs a \"dynamics\" section");
  expect_scene_error(R"({"rigid_bodies": [)" + ground + R"(], "contact": {"stiffness": -1}})", "stiffness");
  expect_scene_error(R"({"rigid_bodies": [)" + ground +
                         R"(, {"primitive": "box", "size": [1, 1, 1], "position": [0, 0, 0.2]}]})",
                     "intersect");
  // A tilted box poking into the ground: all distances positive, but edges cross faces.
  expect_scene_error(
      R"({"rigid_bodies": [)" + ground +
          R"(, {"primitive": "box", "size": [1, 1, 1], "position": [0, 0, 0.55], "rotation": [0.3, 0, 0]}]})",
      "crossings");
  expect_scene_error("{not json", "invalid JSON");
  const std::string box = R"({"primitive": "box", "size": [1, 1, 1], "position": [0, 0, 0.505])";
  expect_scene_error(
      R"({"rigid_bodies": [)" + ground + "," + box + R"(, "kinematic": {"velocity": [1, 0, 0]}}]})",
      "kinematic bodies need a \"dynamics\" section");
  expect_scene_error(
      R"({"rigid_bodies": [)" + ground + "," + box +
          R"(, "fixed": true, "kinematic": {}}], "dynamics": {"time_step": 0.01, "steps": 1}})",
      "either fixed or kinematic");
  expect_scene_error(
      R"({"rigid_bodies": [)" + ground + "," + box +
          R"(, "kinematic": {}, "torque": [0, 0, 1]}], "dynamics": {"time_step": 0.01, "steps": 1}})",
      "rigid_bodies[1].torque");
  expect_scene_error(R"({"rigid_bodies": [)" + ground + R"(], "contact": {"stiffness": "stiff"}})",
                     "contact.stiffness: expected a positive number (a fixed kappa) or \"adaptive\"");
  expect_scene_error(
      R"({"rigid_bodies": [)" + ground + R"(], "contact": {"stiffness": 1e5, "min_stiffness": 1}})",
      "min_stiffness");
  expect_scene_error(R"({"rigid_bodies": [)" + ground + "," + box + R"(, "velocity": [1, 0, 0]}]})",
                     "need a \"dynamics\" section");
}

}  // namespace
}  // namespace tailor::rigid_scene_test
