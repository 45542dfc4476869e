// run_inverse_scene with RunSettings::resume, for every back-end: a run stopped at its iteration
// limit leaves a checkpoint; continued from it with a larger limit, it reaches the minimum that an
// uninterrupted run reaches, the report saying from where it resumed.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "../support/temp_folder.hpp"
#include "problems/fem/inverse_commands.hpp"
#include "problems/json_text.hpp"
#include "problems/optimizer_checkpoint.hpp"

namespace tailor::inverse_resume_test {
namespace {

using TempFolder = tailor::testing::TempFolder;

// The two-material plate pulled along x (tests/problems/resume_cli_test.cpp) on a coarse mesh;
// unbounded, so that ceres_lbfgs takes it too.
std::string plate_scene(const std::string& backend, int max_iterations) {
  return R"({
  "name": "tension_plate",
  "mesh": {"rectangle": {"min": [0, 0], "max": [2, 1], "cells": [8, 4]}},
  "materials": [
    {"elements": {"box": {"min": [0, 0], "max": [1, 1]}}, "model": "neo_hookean", "youngs_modulus": 1e5, "poisson_ratio": 0.3},
    {"elements": {"box": {"min": [1, 0], "max": [2, 1]}}, "model": "neo_hookean", "youngs_modulus": 1e5, "poisson_ratio": 0.3}
  ],
  "dirichlet": [{"vertices": {"plane": {"axis": "x", "value": 0}}}],
  "loads": {"tractions": [{"faces": {"plane": {"axis": "x", "value": 2}}, "traction": [5000, 0]}]},
  "inverse": {
    "design": {"parameter": "youngs_modulus", "granularity": "per_material"},
    "objective": [
      {"type": "synthetic_observations", "vertices": {"box": {"min": [0, 0], "max": [2, 1]}},
       "youngs_modulus": {"materials": [2e5, 2e5]}, "noise": 1e-3, "seed": 1}
    ],
    "optimizer": {"backend": ")" +
         backend + R"(", "max_iterations": )" + std::to_string(max_iterations) +
         R"(, "gradient_tolerance": 1e-9, "checkpoint_every": 2}
  }
})";
}

Scene scene(OptimizerBackend backend, int max_iterations) {
  return parse_scene(plate_scene(to_string(backend), max_iterations), "plate.json", "");
}

class InverseResume : public ::testing::TestWithParam<OptimizerBackend> {};

TEST_P(InverseResume, AStoppedRunContinuesToTheSameMinimum) {
  const OptimizerBackend backend = GetParam();
  TempFolder folder("inverse_resume_" + to_string(backend));
  const InverseRun whole = run_inverse_scene(scene(backend, 300), folder / "whole");
  ASSERT_TRUE(whole.result.converged()) << whole.result.message;
  const int stop = 3;  // before any back-end converges here
  ASSERT_GT(whole.result.history.back().iteration, stop);

  const InverseRun stopped = run_inverse_scene(scene(backend, stop), folder / "part");
  EXPECT_EQ(stopped.result.status, OptimizerStatus::max_iterations) << stopped.result.message;
  const auto checkpoint = read_checkpoint_json(folder / "part").checkpoint;
  EXPECT_EQ(checkpoint.iteration, stop);  // the final checkpoint

  RunSettings settings;
  settings.resume = folder / "part";
  const InverseRun resumed =
      run_inverse_scene(scene(backend, 300), folder / "part", nullptr, nullptr, settings);
  std::cout << to_string(backend) << ": uninterrupted " << whole.result.history.back().iteration
            << " iterations, J = " << whole.result.objective << "; stopped at " << stop << ", resumed to "
            << resumed.result.history.back().iteration << " iterations, J = " << resumed.result.objective
            << "\n";
  ASSERT_TRUE(resumed.result.converged()) << resumed.result.message;
  ASSERT_TRUE(resumed.resumed);
  EXPECT_EQ(resumed.resumed->iteration, stop);
  EXPECT_EQ(resumed.result.resumed_from, stop);
  EXPECT_EQ(resumed.result.history[0].objective, whole.result.history[0].objective);
  // The same minimum to the optimizer's tolerance (J* = 3.1e-6; gradient_tolerance 1e-9).
  EXPECT_NEAR(resumed.result.objective, whole.result.objective, 1e-6 * whole.result.objective);
  EXPECT_NEAR(resumed.design_values[0], whole.design_values[0], 1e-5 * whole.design_values[0]);
  EXPECT_NEAR(resumed.design_values[1], whole.design_values[1], 1e-5 * whole.design_values[1]);
  // The report counts the work of both parts.
  std::ifstream in(folder / "part/report.json");
  const nlohmann::json report = parse_json(in);
  EXPECT_EQ(report["resumed"]["iteration"].get<int>(), stop);
  EXPECT_EQ(report["iterations"].get<int>(), resumed.result.history.back().iteration);
  EXPECT_GT(report["evaluations"].get<int>(), stopped.result.evaluations);
  EXPECT_GT(report["solves"]["forward"].get<int>(), stopped.result.counters.forward_solves);
  // The checkpoint's time (not the stopped run's whole time, which includes work after its last
  // checkpoint) is carried over.
  EXPECT_GE(report["timings"]["optimization"].get<double>(), checkpoint.seconds);
  EXPECT_EQ(parse_json(std::ifstream(folder / "whole/report.json"))["resumed"], nullptr);
}

INSTANTIATE_TEST_SUITE_P(
    EveryBackend, InverseResume,
    ::testing::Values(OptimizerBackend::ipopt, OptimizerBackend::nlopt_lbfgs, OptimizerBackend::nlopt_mma,
                      OptimizerBackend::nlopt_slsqp, OptimizerBackend::ceres_lbfgs,
                      OptimizerBackend::ceres_least_squares, OptimizerBackend::gradient_descent),
    [](const ::testing::TestParamInfo<OptimizerBackend>& param_info) { return to_string(param_info.param); });

}  // namespace
}  // namespace tailor::inverse_resume_test
