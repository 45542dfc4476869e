// The `meshless` scene kind: parsing (unknown keys and bad point files named), simulate's
// report and point VTU files, the kept factorization's steps, modes with warped modal dynamics, the inverse section's Taylor
// test (rate >= 1.9) and a run that recovers a region's Young's modulus from the tip
// displacement it produced.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "forward/solve/newton.hpp"
#include "problems/meshless/meshless_commands.hpp"
#include "problems/meshless/meshless_scene.hpp"
#include "problems/scene_error.hpp"
#include "problems/scene_node.hpp"

namespace tailor::meshless_scene_test {
namespace {

// A 3 x 1 x 1 bar (h = 0.5, 63 nodes), linear material, clamped at x = 0, a tip force.
nlohmann::json bar_scene() {
  return nlohmann::json::parse(R"({
    "meshless": {"shape": {"box": {"lo": [0, 0, 0], "hi": [3, 1, 1]}}, "spacing": 0.5, "quadrature_order": 2, "boundary_depth": 0},
    "material": {"model": "linear", "youngs_modulus": 1000, "poisson_ratio": 0.3, "density": 1},
    "regions": [{"name": "tip", "box": {"lo": [1.5, -1, -1], "hi": [4, 2, 2]}}],
    "fixed": [{"box": {"lo": [-1, -1, -1], "hi": [0, 2, 2]}}],
    "loads": {"forces": [{"at": [3, 0.5, 0.5], "force": [0, 0, -1]}]},
    "modes": {"count": 4, "rayleigh": {"alpha": 0.1, "beta": 0.001}, "time_step": 0.05, "steps": 20, "frame_every": 5,
              "force": {"at": [3, 0.5, 0.5], "force": [0, 0, -10]}},
    "inverse": {"design": "youngs_modulus", "per": "region",
                "observations": [{"at": [3, 0.5, 0.5], "displacement": [0, 0, -0.05]}]}
  })");
}

std::string out_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("tailor_meshless_scene_" + name);
  std::filesystem::remove_all(dir);
  return dir.string();
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

// A SceneNode keeps a pointer to its source's name, which must outlive it.
const std::string kBarSource = "bar.json", kTruthSource = "truth.json";

std::string scene_error(const nlohmann::json& document, const std::string& directory = ".") {
  try {
    const SceneNode root(document, kBarSource, "");
    build_meshless_scene(parse_meshless_scene(root, directory));
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(MeshlessScene, ErrorsNameTheFileAndTheKeyOrPoint) {
  nlohmann::json d = bar_scene();
  d["meshless"]["spacings"] = 1;
  EXPECT_NE(scene_error(d).find("bar.json: meshless.spacings"), std::string::npos) << scene_error(d);
  d = bar_scene();
  d["fixed"][0]["box"]["lo"] = {5, 5, 5};
  d["fixed"][0]["box"]["hi"] = {6, 6, 6};
  EXPECT_NE(scene_error(d).find("fixed[0].box: the box holds no node"), std::string::npos) << scene_error(d);
  d = bar_scene();
  d["meshless"]["refine"] = nlohmann::json::parse(R"([{"box": {"lo": [0, 0, 0], "hi": [1, 1, 1]}, "level": 2}])");
  d["meshless"]["max_level"] = 1;
  EXPECT_NE(scene_error(d).find("bar.json: meshless.refine[0].level: expected at most meshless.max_level (1)"),
            std::string::npos)
      << scene_error(d);
  d["meshless"]["refine"][0]["levels"] = 1;
  EXPECT_NE(scene_error(d).find("meshless.refine[0].levels"), std::string::npos) << scene_error(d);
  d = bar_scene();
  d["loads"]["forces"][0]["at"] = {9, 9, 9};
  EXPECT_NE(scene_error(d).find("loads.forces[0].at: outside the solid"), std::string::npos) << scene_error(d);
  // A point file with a point that has no normal: file and line named.
  const std::string dir = out_dir("points");
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/cloud.xyz") << "0 0 0 0 0 1\n1 0 0 0 0 1\n1 1 0\n";
  d = bar_scene();
  d["meshless"].erase("shape");
  d["meshless"]["points"] = "cloud.xyz";
  const std::string e = scene_error(d, dir);
  EXPECT_NE(e.find("bar.json: meshless.points: "), std::string::npos) << e;
  EXPECT_NE(e.find("cloud.xyz: line 3"), std::string::npos) << e;
}

TEST(MeshlessScene, SimulateWritesTheReportAndPointFiles) {
  const nlohmann::json d = bar_scene();
  const SceneNode root(d, kBarSource, "");
  MeshlessVerbOptions options;
  options.name = "bar";
  options.out_dir = out_dir("simulate");
  std::ostringstream log;
  ASSERT_TRUE(simulate_meshless_scene(root, options, &log)) << log.str();
  const nlohmann::json report = read_json(options.out_dir + "/report.json");
  EXPECT_TRUE(report["converged"].get<bool>());
  EXPECT_EQ(report["discretization"]["nodes"].get<int>(), 63);
  EXPECT_GE(report["discretization"]["fewest_covering_nodes"].get<int>(), 4);
  // Timoshenko tip deflection of this bar, F L^3 / (3 E I) + F L / (kappa G A) = 0.1118; the
  // coarse meshless bar (and the clamped face) lands within 15%.
  const double deflection = report["max_sample_displacement"].get<double>();
  EXPECT_NEAR(deflection, 0.1118, 0.15 * 0.1118);
  std::ifstream vtu(options.out_dir + "/samples.vtu");
  const std::string text((std::istreambuf_iterator<char>(vtu)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("Name=\"displacement\" NumberOfComponents=\"3\""), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(options.out_dir + "/nodes.vtu"));
}

// solver.reuse_factorization: Newton's steps by CG preconditioned with a kept factorization
// (true) reach the state of a factorization per step (false) with fewer factorizations, and
// report.json says how the steps were taken; a bad value is refused with its key path.
TEST(MeshlessScene, KeptFactorizationReachesTheSameStateWithFewerFactorizations) {
  nlohmann::json d = bar_scene();
  d["material"]["model"] = "neo_hookean";  // a Hessian that changes from step to step
  d["loads"]["forces"][0]["force"] = {0, 0, -8};
  nlohmann::json reports[2];
  for (const bool reuse : {false, true}) {
    d["solver"] = {{"reuse_factorization", reuse}, {"max_newton_iterations", 100}};
    const SceneNode root(d, kBarSource, "");
    MeshlessVerbOptions options;
    options.name = "bar";
    options.out_dir = out_dir(reuse ? "reuse_on" : "reuse_off");
    std::ostringstream log;
    ASSERT_TRUE(simulate_meshless_scene(root, options, &log)) << log.str();
    reports[reuse] = read_json(options.out_dir + "/report.json")["newton"];
    reports[reuse]["max_sample_displacement"] = read_json(options.out_dir + "/report.json")["max_sample_displacement"];
  }
  const nlohmann::json &off = reports[0], &on = reports[1];
  EXPECT_EQ(off["reuse_factorization"], "off");
  EXPECT_EQ(on["reuse_factorization"], "on");
  EXPECT_EQ(off["kept_factor_steps"].get<int>(), 0);
  EXPECT_EQ(off["factorizations"].get<int>(), off["iterations"].get<int>());
  EXPECT_GE(off["iterations"].get<int>(), 4);  // nonlinear enough for a kept factor to matter
  EXPECT_GT(on["kept_factor_steps"].get<int>(), 0);
  EXPECT_GT(on["cg_iterations"].get<int>(), 0);
  EXPECT_LT(on["factorizations"].get<int>(), off["factorizations"].get<int>());
  const double u_off = off["max_sample_displacement"].get<double>(), u_on = on["max_sample_displacement"].get<double>();
  EXPECT_GT(u_off, 0.3);
  EXPECT_NEAR(u_on, u_off, 1e-8 * u_off);
  d["solver"] = {{"reuse_factorization", "yes"}};
  EXPECT_NE(scene_error(d).find("bar.json: solver.reuse_factorization: expected true, false or \"auto\""),
            std::string::npos)
      << scene_error(d);
}

// Node levels from a refinement box: the root cells meeting the closed box [0, 1]^3 of the bar
// (h = 0.5: 3 x 2 x 2 of them, x up to 1.5) get nodes at h / 2 (a 7 x 5 x 5 lattice in place
// of 4 x 3 x 3); the report gives the levels and the covering, nodes.vtu each node's level and
// support radius.
TEST(MeshlessScene, RefinementBoxGivesFinerNodesAndTheReportSaysSo) {
  nlohmann::json d = bar_scene();
  d["meshless"]["max_level"] = 1;
  d["meshless"]["refine"] = nlohmann::json::parse(R"([{"box": {"lo": [0, 0, 0], "hi": [1, 1, 1]}, "level": 1}])");
  const SceneNode root(d, kBarSource, "");
  MeshlessVerbOptions options;
  options.name = "bar";
  options.out_dir = out_dir("refined");
  std::ostringstream log;
  ASSERT_TRUE(simulate_meshless_scene(root, options, &log)) << log.str();
  const nlohmann::json report = read_json(options.out_dir + "/report.json");
  const nlohmann::json& r = report["discretization"];
  EXPECT_EQ(r["nodes"].get<int>(), 63 + 7 * 5 * 5 - 4 * 3 * 3) << r.dump();
  EXPECT_EQ(r["cells_refined"].get<int>(), 2 * 2 * 3);
  EXPECT_EQ(r["finest_node_level"].get<int>(), 1);
  EXPECT_EQ(r["covering"]["points"].get<int>(), r["quadrature_points"].get<int>());
  EXPECT_GE(r["fewest_covering_nodes"].get<int>(), 4);
  EXPECT_TRUE(report["converged"].get<bool>());
  std::ifstream vtu(options.out_dir + "/nodes.vtu");
  const std::string text((std::istreambuf_iterator<char>(vtu)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("Name=\"node_level\""), std::string::npos);
  EXPECT_NE(text.find("Name=\"support_radius\""), std::string::npos);
}

// A rotation handle on the end x = 3 of a bar held nowhere else: the neo-Hookean equilibrium
// is the rigid rotation of the whole bar (zero energy), which MLS reproduces exactly, so every
// node's field value is c + R (X - c), c the handle nodes' centroid. Bad rotations are named.
TEST(MeshlessScene, RotationHandleTurnsTheBarRigidly) {
  nlohmann::json d = bar_scene();
  d.erase("fixed");
  d.erase("loads");
  d.erase("inverse");
  d["material"]["model"] = "neo_hookean";
  d["handles"] = nlohmann::json::parse(R"([{"box": {"lo": [3, -1, -1], "hi": [4, 2, 2]},
                                            "rotation": {"axis": [1, 0, 0], "degrees": 30}}])");
  const auto scene = build_meshless_scene(parse_meshless_scene(SceneNode(d, kBarSource, ""), "."));
  NewtonSolver solver(*scene->model);
  Vector y = scene->model->elimination().restrict_state(scene->rest());
  ASSERT_TRUE(solver.solve(scene->p, y).converged());
  const Vector x = scene->model->elimination().expand(y);
  const Eigen::Vector3d c(3.0, 0.5, 0.5);  // the centroid of the end face's 9 nodes
  const Eigen::Matrix3d R = Eigen::AngleAxisd(M_PI / 6.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  double error = 0.0, moved = 0.0;
  for (int a = 0; a < scene->num_nodes(); ++a) {
    const Eigen::Vector3d X = scene->sampling.nodes.row(a).transpose();
    const Eigen::Vector3d expected = c + R * (X - c);
    error = std::max(error, (scene->mls->interpolate(x, X) - expected).norm());
    moved = std::max(moved, (expected - X).norm());
  }
  EXPECT_GT(moved, 0.3);
  EXPECT_LT(error, 1e-8 * moved);

  d["handles"][0]["rotation"]["axis"] = {0, 0, 0};
  EXPECT_NE(scene_error(d).find("bar.json: handles[0].rotation.axis: the rotation axis must not be zero"),
            std::string::npos)
      << scene_error(d);
  d["handles"][0]["rotation"] = nlohmann::json::parse(R"({"axis": [1, 0, 0], "angle": 30})");
  EXPECT_NE(scene_error(d).find("handles[0].rotation.angle"), std::string::npos) << scene_error(d);
  d["handles"][0].erase("rotation");
  EXPECT_NE(scene_error(d).find("handles[0]: a handle needs a displacement, a rotation or both"), std::string::npos)
      << scene_error(d);
}

TEST(MeshlessScene, ModesWithWarpedDynamics) {
  const nlohmann::json d = bar_scene();
  const SceneNode root(d, kBarSource, "");
  MeshlessVerbOptions options;
  options.name = "bar";
  options.out_dir = out_dir("modes");
  ASSERT_TRUE(modes_meshless_scene(root, options, nullptr));
  const nlohmann::json report = read_json(options.out_dir + "/report.json");
  ASSERT_EQ(report["frequencies"].size(), 4u);
  // Rayleigh: zeta = alpha / (2 omega) + beta omega / 2.
  const double f1 = report["frequencies"][0].get<double>(), omega = 2.0 * M_PI * f1;
  EXPECT_NEAR(report["damping_ratios"][0].get<double>(), 0.1 / (2.0 * omega) + 0.001 * omega / 2.0, 1e-12);
  EXPECT_EQ(report["warped_dynamics"]["frames"].get<int>(), 4);
  EXPECT_TRUE(std::filesystem::exists(options.out_dir + "/result.pvd"));
  EXPECT_TRUE(std::filesystem::exists(options.out_dir + "/frames/frame_20.vtu"));
}

// A rotation handle in the warped modal dynamics: the bar held nowhere else, its end x = 0
// turned by 90 degrees about z. The modes leave the handle free (6 rigid modes join the 4
// elastic ones), the handle's springs pull the body round, and at the end of the damped steps
// the handle's nodes sit on their targets and their rotation vectors on the handle's, and every
// sample's rotation angle is 90 degrees: the whole bar has turned rigidly.
TEST(MeshlessScene, RotationHandleTurnsTheWarpedModalBody) {
  nlohmann::json d = bar_scene();
  d.erase("fixed");
  d["modes"].erase("force");
  d["modes"]["rayleigh"] = {{"alpha", 4.0}, {"beta", 0.001}};
  d["modes"]["steps"] = 300;
  d["modes"]["frame_every"] = 100;
  d["handles"] = nlohmann::json::parse(
      R"([{"box": {"lo": [-1, -1, -1], "hi": [0, 2, 2]}, "rotation": {"axis": [0, 0, 1], "degrees": 90}}])");
  const SceneNode root(d, kBarSource, "");
  MeshlessVerbOptions options;
  options.name = "bar";
  options.out_dir = out_dir("modes_handle");
  ASSERT_TRUE(modes_meshless_scene(root, options, nullptr));
  const nlohmann::json report = read_json(options.out_dir + "/report.json");
  const nlohmann::json& w = report["warped_dynamics"];
  EXPECT_EQ(report["rigid_modes"].get<int>(), 6);
  EXPECT_EQ(w["handles"].get<int>(), 1);
  EXPECT_LT(w["handle_position_error"].get<double>(), 1e-6) << w.dump();
  EXPECT_LT(w["handle_rotation_error"].get<double>(), 1e-6) << w.dump();
  EXPECT_NEAR(w["final_rotation_angles"][0].get<double>(), M_PI / 2, 1e-6) << w.dump();
  EXPECT_NEAR(w["final_rotation_angles"][1].get<double>(), M_PI / 2, 1e-6) << w.dump();
}

TEST(MeshlessScene, GradcheckAndRunRecoverTheTipModulus) {
  // The target: the tip displacement that a tip region twice as stiff produces.
  nlohmann::json truth = bar_scene();
  truth["regions"][0]["youngs_modulus"] = 2000;
  MeshlessVerbOptions options;
  options.name = "bar";
  options.out_dir = out_dir("truth");
  ASSERT_TRUE(simulate_meshless_scene(SceneNode(truth, kTruthSource, ""), options, nullptr));
  const auto built = build_meshless_scene(parse_meshless_scene(SceneNode(truth, kTruthSource, ""), "."));
  nlohmann::json d = bar_scene();
  {
    NewtonSolver solver(*built->model);
    Vector y = built->model->elimination().restrict_state(built->rest());
    ASSERT_TRUE(solver.solve(built->p, y).converged());
    const Vector u = built->model->elimination().expand(y) - built->rest();
    // Observed along the bar at x = 1, 2, 3: the deflection curve tells the two moduli apart.
    d["inverse"]["observations"] = nlohmann::json::array();
    for (double x : {1.0, 2.0, 3.0}) {
      const Eigen::Vector3d at(x, 0.5, 0.5), v = built->mls->interpolate(u, at);
      d["inverse"]["observations"].push_back({{"at", {at[0], at[1], at[2]}}, {"displacement", {v[0], v[1], v[2]}}});
    }
  }
  const SceneNode root(d, kBarSource, "");
  options.out_dir = out_dir("gradcheck");
  std::ostringstream log;
  EXPECT_TRUE(gradcheck_meshless_scene(root, options, &log)) << log.str();
  const nlohmann::json check = read_json(options.out_dir + "/gradcheck.json");
  EXPECT_GE(check["rate1"].get<double>(), 1.9) << log.str();

  options.out_dir = out_dir("run");
  ASSERT_TRUE(run_meshless_scene(root, options, &log)) << log.str();
  const nlohmann::json report = read_json(options.out_dir + "/report.json");
  EXPECT_LT(report["objective"].get<double>(), 1e-6 * report["objective_initial"].get<double>()) << log.str();
  // z = log(E / E0) per region [outside the regions, tip]: the tip's modulus doubles.
  std::printf("run: z = [%.5f, %.5f] (truth [0, log 2 = %.5f]), J %.3e -> %.3e\n", report["z"][0].get<double>(),
              report["z"][1].get<double>(), std::log(2.0), report["objective_initial"].get<double>(),
              report["objective"].get<double>());
  EXPECT_NEAR(report["z"][0].get<double>(), 0.0, 1e-6);
  EXPECT_NEAR(report["z"][1].get<double>(), std::log(2.0), 1e-6);
}

}  // namespace
}  // namespace tailor::meshless_scene_test
