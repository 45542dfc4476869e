// `tailor simulate` on dynamic scenes with "dynamics.reduction": the reduced trajectory (full-space
// frames, u = Phi q) approaches the full-space one as the basis grows, the local bases run, the
// report states the basis and r, and scene errors name their key path.
//
// Reference: the full-space run of the same scene (Newmark, the same h), itself checked against
// beam theory and energy behaviour in the dynamics tests; here the reduced model must converge to
// it (Galerkin projection of the same equations of motion).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "problems/fem/dynamic_commands.hpp"
#include "problems/json_text.hpp"
#include "problems/scene_error.hpp"
#include "tests/support/temp_folder.hpp"
#include "tests/support/text_files.hpp"

namespace tailor::reduced_dynamic_scene_test {
namespace {

using namespace tailor::testing;

// A 4 x 0.5 x 0.5 StVK cantilever (8 x 2 x 2 cells, 192 tets), clamped at x = 0, released from
// rest under gravity: the tip falls by about 0.25 (6% of the length) in the 40 Newmark steps.
std::string cantilever(const std::string& reduction) {
  return R"({
  "name": "reduced_swing",
  "mesh": {"box": {"min": [0, 0, 0], "max": [4, 0.5, 0.5], "cells": [8, 2, 2]}},
  "materials": [{"elements": "all", "model": "stvk", "youngs_modulus": 2e6, "poisson_ratio": 0.3, "density": 100}],
  "dirichlet": [{"vertices": {"plane": {"axis": "x", "value": 0}}}],
  "loads": {"gravity": [0, 0, -9.81]},
  "dynamics": {"scheme": "newmark", "time_step": 0.01, "steps": 40, "output_every": 4,
               "rayleigh": {"beta": 0.001})" +
         (reduction.empty() ? std::string() : ", \"reduction\": " + reduction) + "}\n}";
}

// The "displacement" point field of a frame written by write_vtu (ASCII).
std::vector<double> frame_displacement(const std::string& path) {
  const std::string text = read_file(path);
  const auto name = text.find("Name=\"displacement\"");
  EXPECT_NE(name, std::string::npos) << path;
  const auto begin = text.find('>', name) + 1, end = text.find('<', begin);
  std::istringstream in(text.substr(begin, end - begin));
  std::vector<double> values;
  for (double v; in >> v;) values.push_back(v);
  return values;
}

struct Trajectory {
  DynamicRun run;
  std::vector<std::vector<double>> frames;
  nlohmann::json report;
};

Trajectory simulate(const std::string& reduction, const TempFolder& folder, const std::string& tag) {
  const std::string text = cantilever(reduction);
  const Scene scene = parse_scene(text, "swing.json", "");
  Trajectory t;
  t.run = simulate_dynamic_scene(scene, folder / tag, nullptr);
  for (const auto& frame : t.run.frames) t.frames.push_back(frame_displacement(folder / tag + "/" + frame.second));
  std::ifstream in(t.run.report_path);
  t.report = parse_json(in);
  return t;
}

// sqrt(sum over frames and DOFs of (u_r - u_f)^2 / sum of u_f^2).
double trajectory_error(const Trajectory& reduced, const Trajectory& full) {
  double error2 = 0.0, norm2 = 0.0;
  EXPECT_EQ(reduced.frames.size(), full.frames.size());
  for (std::size_t f = 0; f < std::min(reduced.frames.size(), full.frames.size()); ++f)
    for (std::size_t i = 0; i < full.frames[f].size(); ++i) {
      error2 += std::pow(reduced.frames[f][i] - full.frames[f][i], 2);
      norm2 += full.frames[f][i] * full.frames[f][i];
    }
  return std::sqrt(error2 / norm2);
}

TEST(ReducedDynamicScene, TrajectoryApproachesTheFullOneAsTheBasisGrows) {
  TempFolder folder("reduced_dynamic_scene");
  const Trajectory full = simulate("", folder, "full");
  ASSERT_TRUE(full.run.completed) << full.run.message;
  ASSERT_EQ(full.frames.size(), 11u);
  std::vector<double> errors;
  for (int modes : {1, 3, 8}) {
    const Trajectory reduced = simulate(R"({"displacement_modes": )" + std::to_string(modes) +
                                            R"(, "static_responses": false, "derivative_modes": )" +
                                            std::to_string(std::min(modes, 2)) + "}",
                                        folder, "global_" + std::to_string(modes));
    ASSERT_TRUE(reduced.run.completed) << reduced.run.message;
    errors.push_back(trajectory_error(reduced, full));
    const nlohmann::json& r = reduced.report["reduction"];
    EXPECT_EQ(r["basis"], "global");
    EXPECT_EQ(r["energy"], "polynomial");
    EXPECT_EQ(r["reduced_coordinates"].get<int>(), reduced.run.reduction->r);
    std::printf("global, %d modes: r = %d, trajectory error %.3e\n", modes, reduced.run.reduction->r, errors.back());
  }
  EXPECT_LT(errors[1], 0.5 * errors[0]);
  EXPECT_LT(errors[2], 0.5 * errors[1]);
  EXPECT_LT(errors[2], 2e-2);
}

TEST(ReducedDynamicScene, LocalBasesFollowTheFullTrajectory) {
  TempFolder folder("reduced_dynamic_local");
  const Trajectory full = simulate("", folder, "full");
  ASSERT_TRUE(full.run.completed) << full.run.message;
  for (const char* basis : {"domains", "overlapping"}) {
    const std::string domains = std::string(basis) == "domains"
                                    ? R"({"count": 2, "fixed_interface_modes": 4, "interface_modes": 6})"
                                    : R"({"count": 2, "overlap_layers": 1})";
    const Trajectory reduced = simulate(std::string(R"({"basis": ")") + basis + R"(", "domains": )" + domains + "}",
                                        folder, basis);
    ASSERT_TRUE(reduced.run.completed) << reduced.run.message;
    const double error = trajectory_error(reduced, full);
    std::printf("%s: r = %d, %d polynomial groups, trajectory error %.3e\n", basis, reduced.run.reduction->r,
                reduced.run.reduction->groups, error);
    EXPECT_LT(error, 5e-2) << basis;
    EXPECT_EQ(reduced.report["reduction"]["basis"], basis);
    EXPECT_EQ(reduced.report["reduction"]["domains"], 2);
  }
}

TEST(ReducedDynamicScene, SceneErrorsNameTheKeyPath) {
  auto error_of = [](const std::string& reduction) {
    try {
      const Scene scene = parse_scene(cantilever(reduction), "swing.json", "");
      TempFolder folder("reduced_dynamic_errors");
      simulate_dynamic_scene(scene, folder.str(), nullptr);
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of(R"({"displacment_modes": 3})").find("swing.json: dynamics.reduction.displacment_modes"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"basis": "domains", "domains": {"cuont": 2}})").find("dynamics.reduction.domains.cuont"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"basis": "domains", "krylov_order": 3})").find("dynamics.reduction.krylov_order"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"domains": {"count": 2}})").find("dynamics.reduction.domains: only with"), std::string::npos);
  EXPECT_NE(error_of(R"({"basis": "overlapping", "domains": {"interface_modes": 2}})")
                .find("dynamics.reduction.domains.interface_modes"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"basis": "domains", "domains": {"count": 100000}})").find("dynamics.reduction:"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"energy": "cubic"})").find("dynamics.reduction.energy"), std::string::npos);
  EXPECT_EQ(error_of(R"({"displacement_modes": 2})"), "no error");  // the check above can pass
  // The transient adjoint is full-space: gradcheck of a reduced scene is refused, naming the section.
  std::string text = cantilever(R"({"displacement_modes": 2})");
  const std::string every = R"("output_every": 4,)";
  text.replace(text.find(every), every.size(),
               R"("output_every": 4, "objective": {"vertices": {"list": [0]}, "target": [0, 0, 0]},)");
  const Scene with_objective = parse_scene(text, "swing.json", "");
  TempFolder folder("reduced_dynamic_gradcheck");
  try {
    gradcheck_dynamic_scene(with_objective, folder.str(), 1, nullptr);
    ADD_FAILURE() << "gradcheck of a reduced dynamic scene ran";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("swing.json: dynamics.reduction: gradcheck"), std::string::npos) << e.what();
  }
}

// "rotations": "domains" steps the same basis in the subspace that turns with each domain
// (RotatingSubspaceDynamics): on the swinging cantilever (small rotations) it must follow the
// full-space run as closely as the fixed basis does, and report its rotations and blend.
// Measured: 2.0e-4 with the quaternion blend against 2.5e-4 for the fixed basis (the "nearest"
// blend, frames that jump across the overlaps, gives 1.0e-2, which this bound rejects).
TEST(ReducedDynamicScene, TurningDomainsFollowTheFullTrajectory) {
  TempFolder folder("reduced_dynamic_rotations");
  const Trajectory full = simulate("", folder, "full");
  ASSERT_TRUE(full.run.completed) << full.run.message;
  const std::string base = R"({"basis": "overlapping", "domains": {"count": 2, "overlap_layers": 1})";
  const Trajectory fixed = simulate(base + "}", folder, "fixed");
  ASSERT_TRUE(fixed.run.completed) << fixed.run.message;
  EXPECT_EQ(fixed.report["reduction"]["rotations"], "none");
  for (const char* blend : {"quaternion"}) {
    const Trajectory turned =
        simulate(base + R"(, "rotations": "domains", "rotation_blend": ")" + blend + "\"}", folder, blend);
    ASSERT_TRUE(turned.run.completed) << turned.run.message;
    const double error = trajectory_error(turned, full), fixed_error = trajectory_error(fixed, full);
    std::printf("overlapping, rotations (%s): r = %d, trajectory error %.3e (fixed basis %.3e)\n", blend,
                turned.run.reduction->r, error, fixed_error);
    EXPECT_LT(error, 2.0 * fixed_error + 1e-3) << blend;
    EXPECT_EQ(turned.report["reduction"]["rotations"], "domains");
    EXPECT_EQ(turned.report["reduction"]["rotation_blend"], blend);
    EXPECT_EQ(turned.report["reduction"]["energy"], "projected");
    // The energy records are the full-space quantities: the swing starts at rest (E = 0 at
    // step 0) and damping keeps the total at or below it.
    for (const auto& record : turned.run.records) EXPECT_LT(record.kinetic + record.potential, 1e-9);
  }
}

TEST(ReducedDynamicScene, RotationKeysAreChecked) {
  auto error_of = [](const std::string& reduction, const std::string& scheme) {
    try {
      std::string text = cantilever(reduction);
      text.replace(text.find("\"newmark\""), 9, "\"" + scheme + "\"");
      const Scene scene = parse_scene(text, "swing.json", "");
      TempFolder folder("reduced_dynamic_rotation_errors");
      simulate_dynamic_scene(scene, folder.str(), nullptr);
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string overlapping = R"({"basis": "overlapping", "domains": {"count": 2, "overlap_layers": 1}, )";
  EXPECT_NE(error_of(overlapping + R"("rotations": "yes"})", "newmark").find("swing.json: dynamics.reduction.rotations"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"rotations": "domains"})", "newmark").find("dynamics.reduction.rotations: \"domains\" needs"),
            std::string::npos);
  EXPECT_NE(error_of(overlapping + R"("rotation_blend": "nearest"})", "newmark")
                .find("dynamics.reduction.rotation_blend: only with"),
            std::string::npos);
  EXPECT_NE(error_of(overlapping + R"("rotations": "domains", "rotation_blend": "slerp"})", "newmark")
                .find("dynamics.reduction.rotation_blend"),
            std::string::npos);
  EXPECT_NE(error_of(overlapping + R"("rotations": "domains", "energy": "polynomial"})", "newmark")
                .find("dynamics.reduction.rotations"),
            std::string::npos);
  EXPECT_NE(error_of(overlapping + R"("rotations": "domains"})", "implicit_euler").find("swing.json: dynamics.scheme"),
            std::string::npos);
  // The checks can pass (a cheap run: the global basis with rotations off).
  EXPECT_EQ(error_of(R"({"rotations": "none", "displacement_modes": 2})", "implicit_euler"), "no error");
}

TEST(ReducedDynamicScene, ShippedExampleParses) {
  const Scene scene = read_scene(kScenesDir + "/reduced_swinging_beam.json");
  ASSERT_TRUE(scene.dynamics && scene.dynamics->reduction);
  EXPECT_EQ(scene.dynamics->reduction->basis, "overlapping");
  EXPECT_EQ(scene.dynamics->reduction->domains.count, 3);
}

}  // namespace
}  // namespace tailor::reduced_dynamic_scene_test
