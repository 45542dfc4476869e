// A forward solve that fails inside an optimization is a failed trial point, for every
// back-end: Newton does not converge there, StaticFunctional raises EvaluationError, the
// back-end backs off (shorter step, smaller trust region), the run goes on to the minimum and
// the report counts the point.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "../support/temp_folder.hpp"
#include "problems/fem/inverse_commands.hpp"
#include "problems/json_text.hpp"

namespace tailor::failed_solves_test {
namespace {

using TempFolder = tailor::testing::TempFolder;

// A 2D plate of two neo-Hookean halves pulled along x; the moduli of both (truth 2e5, noisy
// observations of every vertex) start 10x too stiff, in [1e2, 1e8] (unbounded for ceres_lbfgs,
// which takes no bounds). The first steps of every back-end try far softer plates, whose stretch
// under the load Newton cannot reach in its 4 iterations (solver.max_iterations), while the
// solves near the iterates converge in 2-3. The gradient tolerance sits above the gradient's
// noise floor (about 1e-9 here, from the forward solves' tolerance), where plain gradient
// descent's line search would otherwise stall one step short of it.
std::string plate_scene(const std::string& backend) {
  const std::string bounds = backend == "ceres_lbfgs" ? "" : R"(, "min": 1e2, "max": 1e8)";
  return R"({
  "name": "failing_plate",
  "mesh": {"rectangle": {"min": [0, 0], "max": [2, 1], "cells": [8, 4]}},
  "materials": [
    {"elements": {"box": {"min": [0, 0], "max": [1, 1]}}, "model": "neo_hookean", "youngs_modulus": 1e5, "poisson_ratio": 0.3},
    {"elements": {"box": {"min": [1, 0], "max": [2, 1]}}, "model": "neo_hookean", "youngs_modulus": 1e5, "poisson_ratio": 0.3}
  ],
  "solver": {"max_iterations": 4},
  "dirichlet": [{"vertices": {"plane": {"axis": "x", "value": 0}}}],
  "loads": {"tractions": [{"faces": {"plane": {"axis": "x", "value": 2}}, "traction": [5000, 0]}]},
  "inverse": {
    "design": {"parameter": "youngs_modulus", "granularity": "per_material", "initial": 2e6)" +
         bounds + R"(},
    "objective": [
      {"type": "synthetic_observations", "vertices": {"box": {"min": [0, 0], "max": [2, 1]}},
       "youngs_modulus": {"materials": [2e5, 2e5]}, "noise": 1e-3, "seed": 1}
    ],
    "optimizer": {"backend": ")" +
         backend + R"(", "max_iterations": 300, "gradient_tolerance": 1e-8}
  }
})";
}

// The scene's functional, recording why evaluations failed.
class Recording : public ReducedFunctional {
 public:
  explicit Recording(ReducedFunctional& inner) : inner_(inner) {}
  int size() const override { return inner_.size(); }
  double value(const Vector& z) override {
    return record([&] { return inner_.value(z); });
  }
  double value_and_gradient(const Vector& z, Vector& g) override {
    return record([&] { return inner_.value_and_gradient(z, g); });
  }
  bool has_residuals() const override { return inner_.has_residuals(); }
  int num_residuals() const override { return inner_.num_residuals(); }
  void residuals(const Vector& z, Vector& r, Matrix* J) override {
    record([&] {
      inner_.residuals(z, r, J);
      return 0.0;
    });
  }
  const FunctionalCounters& counters() const override { return inner_.counters(); }
  int failures = 0;
  int newton_failures = 0;  // "forward solve failed: max_iterations (...)"

 private:
  template <typename F>
  double record(F&& f) {
    try {
      return f();
    } catch (const EvaluationError& e) {
      ++failures;
      if (std::string(e.what()).find("forward solve failed: max_iterations") != std::string::npos)
        ++newton_failures;
      throw;
    }
  }
  ReducedFunctional& inner_;
};

class FailedSolves : public ::testing::TestWithParam<OptimizerBackend> {};

TEST_P(FailedSolves, AreFailedTrialPointsAndTheRunGoesOn) {
  const Scene scene = parse_scene(plate_scene(to_string(GetParam())), "plate.json", "");
  const auto problem = build_inverse_problem(scene);
  Recording functional(*problem->functional);
  const OptimizerResult result =
      minimize(functional, problem->z0, problem->bounds, {}, problem->spec.optimizer);
  std::cout << to_string(GetParam()) << ": " << result.failed_evaluations << " failed of "
            << result.evaluations << " evaluations, " << result.history.back().iteration << " iterations; "
            << result.message << "\n";
  // Trial points failed, and for the reason wanted: Newton did not converge there.
  EXPECT_GT(functional.newton_failures, 0);
  EXPECT_EQ(result.failed_evaluations, functional.failures);
  // The run went on to the minimum: both moduli at the truth up to the observations' noise.
  ASSERT_TRUE(result.converged()) << result.message;
  const Eigen::VectorXd E = problem->design_values(result.z);
  EXPECT_NEAR(E[0], 2e5, 1e-3 * 2e5);
  EXPECT_NEAR(E[1], 2e5, 1e-3 * 2e5);
  EXPECT_NE(result.report().find("failed points  : " + std::to_string(result.failed_evaluations)),
            std::string::npos)
      << result.report();
}

INSTANTIATE_TEST_SUITE_P(
    EveryBackend, FailedSolves,
    ::testing::Values(OptimizerBackend::ipopt, OptimizerBackend::nlopt_lbfgs, OptimizerBackend::nlopt_mma,
                      OptimizerBackend::nlopt_slsqp, OptimizerBackend::ceres_lbfgs,
                      OptimizerBackend::ceres_least_squares, OptimizerBackend::gradient_descent),
    [](const ::testing::TestParamInfo<OptimizerBackend>& param_info) { return to_string(param_info.param); });

TEST(FailedSolvesReport, AreCountedInReportJson) {
  TempFolder folder("failed_solves_report");
  const InverseRun run =
      run_inverse_scene(parse_scene(plate_scene("gradient_descent"), "plate.json", ""), folder / "out");
  ASSERT_TRUE(run.result.converged()) << run.result.message;
  EXPECT_GT(run.result.failed_evaluations, 0);
  std::ifstream in(folder / "out/report.json");
  const nlohmann::json report = parse_json(in);
  EXPECT_EQ(report["failed_evaluations"].get<int>(), run.result.failed_evaluations);
  EXPECT_EQ(report["status"], "converged");
}

}  // namespace
}  // namespace tailor::failed_solves_test
