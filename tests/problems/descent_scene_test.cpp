// `dynamics.solver` of dynamic scenes: the descent method (forward/dynamics/descent_solver.hpp)
// runs `tailor simulate` to the same trajectory as Newton (the small box has vertices fixed in
// some components only, so the preconditioner's partial blocks are exercised), its keys are
// checked with key paths, and `tailor gradcheck` refuses it with the reason.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "../support/temp_folder.hpp"
#include "problems/fem/dynamic_commands.hpp"
#include "problems/fem/dynamic_scene.hpp"
#include "problems/json_text.hpp"
#include "problems/scene_error.hpp"
#include "scene_text.hpp"

namespace tailor::descent_scene_test {
namespace {

using namespace tailor::testing;

std::string dynamic_box(const std::string& solver) {
  const std::string text = with(R"("youngs_modulus": 1000, "poisson_ratio": 0.3})",
                                R"("youngs_modulus": 1000, "poisson_ratio": 0.3, "density": 1})");
  return with(R"("solver": {"load_steps": 1})",
              R"("solver": {"load_steps": 1}, "dynamics": {"scheme": "newmark", "time_step": 0.05, "steps": 6,
              "rayleigh": {"alpha": 0.5, "beta": 0.01}, "output_every": 6,
              "objective": {"vertices": {"plane": {"axis": "x", "value": 2}}, "target": [0.01, 0, 0]},
              "solver": )" + solver + "}",
              text);
}

std::string error_of(const std::string& solver) {
  try {
    parse_scene(dynamic_box(solver), "box.json", "");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "no error";
}

TEST(DescentScene, ParsesItsKeysWithKeyPaths) {
  const Scene scene = parse_scene(
      dynamic_box(R"({"method": "descent", "max_iterations": 50, "relative_tolerance": 1e-5, "rho": 0.9,
                     "step_length": 0.5, "rho_estimation_iterations": 8})"),
      "box.json", "");
  EXPECT_EQ(scene.dynamics->solver_method, "descent");
  EXPECT_EQ(scene.dynamics->descent.max_iterations, 50);
  EXPECT_DOUBLE_EQ(scene.dynamics->descent.relative_tolerance, 1e-5);
  EXPECT_DOUBLE_EQ(*scene.dynamics->descent.rho, 0.9);
  EXPECT_DOUBLE_EQ(scene.dynamics->descent.step_length, 0.5);
  EXPECT_EQ(scene.dynamics->descent.rho_estimation_iterations, 8);
  EXPECT_EQ(parse_scene(dynamic_box(R"({})"), "box.json", "").dynamics->solver_method, "newton");
  EXPECT_NE(error_of(R"({"method": "jacobi"})").find("dynamics.solver.method"), std::string::npos);
  EXPECT_NE(error_of(R"({"method": "descent", "rho": 1.0})").find("dynamics.solver.rho"), std::string::npos);
  EXPECT_NE(error_of(R"({"method": "descent", "omega": 1})").find("dynamics.solver.omega"), std::string::npos);
  EXPECT_NE(error_of(R"({"rho": 0.5})").find("applies to \"method\": \"descent\" only"), std::string::npos);
}

TEST(DescentScene, DeviceAndPreconditionerKeys) {
  const Scene scene = parse_scene(
      dynamic_box(R"({"method": "descent", "device": "cpu", "preconditioner": "vertex_blocks"})"), "box.json", "");
  EXPECT_EQ(scene.dynamics->descent.device, DescentDevice::cpu);
  EXPECT_EQ(scene.dynamics->descent.preconditioner, DescentPreconditioner::vertex_blocks);
  EXPECT_NE(error_of(R"({"method": "descent", "device": "tpu"})").find("dynamics.solver.device"), std::string::npos);
  EXPECT_NE(error_of(R"({"method": "descent", "preconditioner": "ilu"})").find("dynamics.solver.preconditioner"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"device": "gpu"})").find("applies to \"method\": \"descent\" only"), std::string::npos);
  // "gpu" where no device is usable: a scene error naming the key, not a crash or a silent CPU run.
  const Scene gpu = parse_scene(dynamic_box(R"({"method": "descent", "device": "gpu", "preconditioner": "vertex_blocks"})"),
                                "box.json", "");
  TempFolder folder("descent_scene_gpu");
  try {
    simulate_dynamic_scene(gpu, folder.str(), nullptr);
    GTEST_SKIP() << "a CUDA device ran the scene";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("dynamics.solver.device"), std::string::npos) << e.what();
  }
}

TEST(DescentScene, SimulatesNewtonsTrajectory) {
  // Reference: the same scene stepped by Newton (relative tolerance 1e-10); descent at 1e-9.
  auto energies = [](const std::string& solver, const char* tag) {
    const Scene scene = parse_scene(dynamic_box(solver), "box.json", "");
    TempFolder folder(tag);
    const DynamicRun run = simulate_dynamic_scene(scene, folder.str(), nullptr);
    EXPECT_TRUE(run.completed) << run.message;
    std::ifstream in(run.report_path);
    const nlohmann::json report = parse_json(in);
    EXPECT_EQ(report["dynamics"]["solver"], scene.dynamics->solver_method);
    std::vector<double> e;
    for (const DynamicStepRecord& r : run.records) e.push_back(r.kinetic + r.potential);
    return e;
  };
  const std::vector<double> newton = energies(R"({"method": "newton"})", "descent_scene_newton");
  const std::vector<double> descent =
      energies(R"({"method": "descent", "relative_tolerance": 1e-9, "max_iterations": 20000})",
               "descent_scene_descent");
  ASSERT_EQ(newton.size(), descent.size());
  for (std::size_t n = 1; n < newton.size(); ++n)
    EXPECT_NEAR(descent[n], newton[n], 1e-6 * std::abs(newton[0] - newton[n]) + 1e-12) << "step " << n;
}

TEST(DescentScene, GradcheckRefusesDescentWithTheReason) {
  const Scene scene = parse_scene(dynamic_box(R"({"method": "descent"})"), "box.json", "");
  TempFolder folder("descent_gradcheck");
  try {
    gradcheck_dynamic_scene(scene, folder.str(), 1, nullptr);
    FAIL() << "gradcheck ran with descent";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("dynamics.solver.method"), std::string::npos) << what;
    EXPECT_NE(what.find("transient adjoint needs each step solved by Newton"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace tailor::descent_scene_test
