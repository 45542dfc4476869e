// Rigid joints: the L-frame of scenes/rods/rod_l_frame.json. A column of length L1 = 1 clamped at
// its base (0, 0, 0) rises along y to a corner (0, 1, 0), where a rigid joint welds it to a beam
// of length L2 = 1 along x; the beam's free end carries a small load P. EI = 1, EA = 400 (r = 0.1),
// GJ = EI / (1 + nu) with nu = 0.3 (the scene's default shear modulus E / 2.6).
// Reference (linear frame analysis, Castigliano's theorem, by hand):
//  - in-plane load P along -y at the tip: beam moment P s (s from the tip), column moment P L2
//    and axial force P, so U = P^2 L2^3 / (6 EI) + P^2 L2^2 L1 / (2 EI) + P^2 L1 / (2 EA) and
//    delta_y = dU/dP = P (L2^3 / 3 + L2^2 L1) / EI + P L1 / EA;
//  - load P along z (normal to the frame's plane): the beam bends (P L2^3 / 3EI), the column
//    bends under the shear P (P L1^3 / 3EI) and twists under the torque P L2, turning the beam
//    by P L2 L1 / GJ, so delta_z = P (L2^3 + L1^3) / (3 EI) + P L2^2 L1 / GJ.
// The column uses the staggered clamp of tests/forward/rods (its first edge centred on the
// base); the members meet at a vertex (the joint). With a pinned joint instead of the rigid
// one the frame is a mechanism (the beam turns freely about the corner).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "../../support/report_checks.hpp"
#include "../../support/temp_folder.hpp"
#include "forward/core/symmetric_eigen.hpp"
#include "problems/fem/scene.hpp"
#include "problems/rods/rod_scene.hpp"
#include "rod_scene_files.hpp"

namespace tailor::rod_l_frame_test {
namespace {

using testing::read_rod_scene;

constexpr double kP = 1e-5, kEI = 1.0, kEA = 400.0, kGJ = 1.0 / 1.3;

// The frame with n edges per member and the tip load along `direction`.
nlohmann::json l_frame(int n, const Eigen::Vector3d& direction) {
  nlohmann::json s = read_rod_scene("rod_l_frame.json");
  const double h = 1.0 / (n - 0.5);
  s["rods"][0]["line"]["from"] = {0.0, -0.5 * h, 0.0};
  s["rods"][0]["line"]["vertices"] = n + 1;
  s["rods"][1]["line"]["vertices"] = n + 1;
  s["rods"][1]["point_loads"][0]["vertex"] = n;
  s["rods"][1]["point_loads"][0]["force"] = {kP * direction.x(), kP * direction.y(), kP * direction.z()};
  return s;
}

// Tip displacement of the frame scene (the beam's last vertex), and that the joint held.
Eigen::Vector3d tip_displacement(const nlohmann::json& scene, int n) {
  const RodSceneSpec spec = parse_rod_scene(scene);
  const auto dir = testing::unique_temp_path("tailor_rod_l_frame_" + std::to_string(n));
  const RodSimulation sim = simulate_rods(spec, dir.string());
  if (!sim.converged) {
    std::ifstream r(sim.report_path);
    std::cout << r.rdbuf() << std::endl;
  }
  EXPECT_TRUE(sim.converged);
  testing::expect_report_header(sim.report_path);
  std::filesystem::remove_all(dir);
  const int corner = 3 * n, start = 3 * (n + 1), tip = 3 * (2 * n + 1);
  EXPECT_NEAR((sim.state.segment<3>(corner) - sim.state.segment<3>(start)).norm(), 0.0, 1e-15);
  return sim.state.segment<3>(tip) - Eigen::Vector3d(1.0, 1.0, 0.0);
}

TEST(RodRigidJointFrame, InPlaneTipLoadMatchesCastigliano) {
  const double reference = -kP * (1.0 / 3.0 + 1.0) / kEI - kP / kEA;
  std::vector<double> errors;
  for (int n : {10, 20, 40}) {
    const Eigen::Vector3d u = tip_displacement(
        n == 20 ? read_rod_scene("rod_l_frame.json") : l_frame(n, -Eigen::Vector3d::UnitY()), n);
    EXPECT_LT(std::abs(u.z()), 1e-12);
    errors.push_back(std::abs(u.y() / reference - 1.0));
  }
  std::printf(
      "L-frame, in-plane tip load: deflection %.6e (reference); relative errors at n = 10, 20, 40: "
      "%.3e %.3e %.3e\n",
      reference, errors[0], errors[1], errors[2]);
  for (std::size_t i = 1; i < errors.size(); ++i) EXPECT_GT(std::log2(errors[i - 1] / errors[i]), 1.8);
  EXPECT_LT(errors.back(), 1e-4);
}

TEST(RodRigidJointFrame, OutOfPlaneTipLoadMatchesCastigliano) {
  const double reference = kP * (2.0 / 3.0) / kEI + kP / kGJ;
  std::vector<double> errors;
  for (int n : {10, 20, 40}) {
    const Eigen::Vector3d u = tip_displacement(l_frame(n, Eigen::Vector3d::UnitZ()), n);
    errors.push_back(std::abs(u.z() / reference - 1.0));
  }
  std::printf(
      "L-frame, out-of-plane tip load: deflection %.6e (reference); relative errors at n = 10, 20, 40: "
      "%.3e %.3e %.3e\n",
      reference, errors[0], errors[1], errors[2]);
  for (std::size_t i = 1; i < errors.size(); ++i) EXPECT_GT(std::log2(errors[i - 1] / errors[i]), 1.8);
  EXPECT_LT(errors.back(), 1e-4);
}

// Smallest and largest eigenvalue of the reduced exact Hessian at the drawn (rest) state.
Eigen::Vector2d extreme_eigenvalues(const nlohmann::json& scene) {
  const RodSceneSpec spec = parse_rod_scene(scene);
  RodSceneModel m = build_rod_model(spec);
  SparseMatrix H(m.rest.size(), m.rest.size());
  for (const auto& term : m.model->terms()) H += term->hessian(m.rest, m.p, HessianMode::exact);
  const SparseMatrix& S = m.model->elimination().basis();
  const Matrix reduced = Matrix(S.transpose() * H * S);
  const Vector ev = symmetric_eigenvalues(reduced);
  return {ev[0], ev[ev.size() - 1]};
}

// With a pinned joint the same frame is a mechanism: the beam turns about the corner (and
// spins about its axis) at no cost, so the reduced Hessian is singular; the rigid joint makes it
// positive definite.
TEST(RodRigidJointFrame, WithAPinnedJointTheFrameIsAMechanism) {
  nlohmann::json s = read_rod_scene("rod_l_frame.json");
  const Eigen::Vector2d rigid = extreme_eigenvalues(s);
  s["joints"][0]["type"] = "pinned";
  const Eigen::Vector2d pinned = extreme_eigenvalues(s);
  std::printf("L-frame reduced Hessian: smallest / largest eigenvalue %.3e (rigid), %.3e (pinned)\n",
              rigid[0] / rigid[1], pinned[0] / pinned[1]);
  EXPECT_GT(rigid[0] / rigid[1], 1e-9);
  EXPECT_LT(std::abs(pinned[0] / pinned[1]), 1e-13);
}

// A T-frame: the beam runs through the joint (a member at its interior vertex: both edges
// coupled) and carries equal loads P along -y at both tips. Reference: by symmetry the joint does
// not turn, so each half is a cantilever from the corner and the column is only compressed (by
// 2P): delta = P L2^3 / (3 EI) + 2 P L1 / EA.
TEST(RodRigidJointFrame, BeamThroughTheJointUnderSymmetricLoads) {
  const int n = 20;
  nlohmann::json s = l_frame(n, -Eigen::Vector3d::UnitY());
  s["rods"][1]["line"]["from"] = {-1.0, 1.0, 0.0};
  s["rods"][1]["line"]["vertices"] = 2 * n + 1;
  s["rods"][1]["point_loads"] = {{{"vertex", 0}, {"force", {0.0, -kP, 0.0}}},
                                 {{"vertex", 2 * n}, {"force", {0.0, -kP, 0.0}}}};
  s["joints"][0]["rods"][1]["vertex"] = n;
  const RodSceneSpec spec = parse_rod_scene(s);
  RodSceneModel m = build_rod_model(spec);
  ASSERT_EQ(m.rigid_joints.size(), 1u);
  EXPECT_EQ(m.rigid_joints[0]->num_members(), 3);  // the column's last edge, the beam's two middle edges
  const auto dir = testing::unique_temp_path("tailor_rod_t_frame");
  const RodSimulation sim = simulate_rods(spec, dir.string());
  std::filesystem::remove_all(dir);
  EXPECT_TRUE(sim.converged);
  const double reference = -kP / (3.0 * kEI) - 2.0 * kP / kEA;
  const int left = 3 * (n + 1), right = 3 * (n + 1 + 2 * n);
  const double dl = sim.state[left + 1] - 1.0, dr = sim.state[right + 1] - 1.0;
  std::printf("T-frame: tip deflections %.6e %.6e, reference %.6e\n", dl, dr, reference);
  EXPECT_NEAR(dl, dr, 1e-9 * std::abs(reference));
  // 8.5e-4; with the beam's own stencil at the joint kept as well the vertex would be twice as
  // stiff and the error 3.6e-2 (3h / 4L).
  EXPECT_LT(std::abs(dl / reference - 1.0), 2e-3);
  EXPECT_LT(sim.state.tail<3>().norm(), 1e-9);  // the joint does not turn
}

TEST(RodRigidJointFrame, RigidJointsWithDynamicsAreRefused) {
  nlohmann::json s = read_rod_scene("rod_l_frame.json");
  s["rods"][0]["material"]["density"] = 1000.0;
  s["rods"][1]["material"]["density"] = 1000.0;
  s["dynamics"] = {{"scheme", "newmark"}, {"time_step", 0.01}, {"steps", 2}};
  try {
    parse_rod_scene(s);
    ADD_FAILURE() << "expected an error naming joints[0].type";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("joints[0].type"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tailor::rod_l_frame_test
