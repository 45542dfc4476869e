// report.json carries every documented key, consistent with the solution; the CLI maps
// outcomes to exit codes and error messages.
#include "problems/fem/report.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "../support/report_checks.hpp"
#include "../support/temp_folder.hpp"
#include "../support/text_files.hpp"
#include "forward/solve/blas_info.hpp"
#include "problems/fem/commands.hpp"
#include "problems/json_text.hpp"
#include "scene_text.hpp"
#include "tests/support/test_paths.hpp"

namespace tailor::report_test {
namespace {

namespace fs = std::filesystem;

using TempFolder = tailor::testing::TempFolder;

using tailor::testing::read_file;
using tailor::testing::write_file;
TEST(Report, HasEveryDocumentedKey) {
  TempFolder folder("problems_report");
  const Scene scene = parse_scene(testing::with("\"load_steps\": 1", "\"load_steps\": 2"), "box.json", "");
  const SimulateRun run = simulate_scene(scene, folder / "out");
  ASSERT_TRUE(run.solution.converged);
  ASSERT_TRUE(fs::exists(folder / "out/result.vtu"));
  const auto report = parse_json(read_file(folder / "out/report.json"));
  testing::expect_report_header(folder / "out/report.json");

  for (const char* key : {"tailor_version", "report_format", "scene", "status", "message", "converged",
                          "iterations", "linear_solver", "load_steps", "residual_history", "energy_history",
                          "timings", "mesh", "dofs", "results"})
    EXPECT_TRUE(report.contains(key)) << key;
  for (const char* key :
       {"total", "setup", "analysis", "assembly", "factorization", "solve", "line_search", "output"})
    EXPECT_TRUE(report["timings"][key].is_number()) << key;
  for (const char* key : {"max_displacement", "max_displacement_vertex", "energy", "reaction_force_total",
                          "applied_force_total"})
    EXPECT_TRUE(report["results"].contains(key)) << key;
  for (const char* key : {"load_factor", "status", "message", "iterations", "initial_residual",
                          "final_residual", "residual_floor", "floor_ratio", "accuracy", "solution_change",
                          "condition_estimate", "energy", "seconds"})
    EXPECT_TRUE(report["load_steps"][0].contains(key)) << key;

  EXPECT_EQ(report["scene"]["name"], "box");
  EXPECT_EQ(report["scene"]["source"], "box.json");
  EXPECT_EQ(report["status"], "converged");
  EXPECT_EQ(report["linear_solver"], nlohmann::json({{"name", "cholmod"}}));
  EXPECT_EQ(report["converged"], true);
  EXPECT_EQ(report["load_steps"].size(), 2u);
  EXPECT_EQ(report["mesh"]["dim"], 3);
  EXPECT_EQ(report["mesh"]["vertices"], run.setup.mesh.num_vertices());
  EXPECT_EQ(report["mesh"]["elements"], run.setup.mesh.num_elements());
  EXPECT_EQ(report["dofs"]["total"], run.setup.num_dofs());
  EXPECT_EQ(report["dofs"]["free"].get<int>() + report["dofs"]["fixed"].get<int>(), run.setup.num_dofs());
  // One residual per iterate: iterations + 1 per load step.
  const int iterations = report["iterations"];
  EXPECT_EQ(report["residual_history"].size(), static_cast<std::size_t>(iterations + 2));
  EXPECT_EQ(report["energy_history"].size(), report["residual_history"].size());
  EXPECT_DOUBLE_EQ(report["results"]["max_displacement"].get<double>(), run.solution.max_displacement);
  EXPECT_EQ(report["results"]["reaction_force_total"].size(), 3u);
  EXPECT_NEAR(report["results"]["applied_force_total"][0].get<double>(), 1.0, 1e-12);
}

TEST(Report, FailedSolveStillWritesTheReport) {
  TempFolder folder("problems_failed");
  // One iteration cannot converge a large Neo-Hookean stretch.
  std::string json = testing::with("\"model\": \"linear\"", "\"model\": \"neo_hookean\"");
  json = testing::with("\"traction\": [1, 0, 0]", "\"traction\": [300, 0, 0]", json);
  json = testing::with("\"load_steps\": 1", "\"load_steps\": 1, \"max_iterations\": 1", json);
  const SimulateRun run = simulate_scene(parse_scene(json, "box.json", ""), folder.str());
  EXPECT_FALSE(run.solution.converged);
  const auto report = parse_json(read_file(folder / "report.json"));
  EXPECT_EQ(report["status"], "max_iterations");
  EXPECT_EQ(report["converged"], false);
  EXPECT_FALSE(report["message"].get<std::string>().empty());
}

// Runs the tailor executable after `prefix` (e.g. "env VAR=value"); returns its exit code, with
// stdout and stderr in `output`.
int run_cli_with(const std::string& prefix, const std::string& arguments, const std::string& log,
                 std::string& output) {
  const std::string command = prefix + " " + std::string(::tailor::testing::binary_dir()) + "/bin/tailor " +
                              arguments + " > " + log + " 2>&1";
  const int status = std::system(command.c_str());
  output = read_file(log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

int run_cli(const std::string& arguments, const std::string& log, std::string& output) {
  return run_cli_with("", arguments, log, output);
}

TEST(Cli, BadSceneExitsWithTwoAndNamesTheKey) {
  TempFolder folder("problems_cli_bad");
  write_file(folder / "beam.json", testing::with("\"poisson_ratio\": 0.3", "\"poisson_ratio\": 0.5"));
  std::string output;
  EXPECT_EQ(
      run_cli("simulate " + (folder / "beam.json") + " --out " + (folder / "out"), folder / "log", output),
      2);
  EXPECT_NE(output.find("beam.json: materials[0].poisson_ratio: expected a number in (-1, 0.5), got 0.5"),
            std::string::npos)
      << output;
  EXPECT_FALSE(fs::exists(folder / "out/report.json"));
}

TEST(Cli, DefaultJobConverges) {
  TempFolder folder("problems_cli_default");
  std::string output;
  ASSERT_EQ(run_cli("simulate --out " + (folder / "out"), folder / "log", output), 0) << output;
  EXPECT_NE(output.find("built-in cantilever"), std::string::npos) << output;
  EXPECT_NE(output.find("newton"), std::string::npos) << output;
  const auto report = parse_json(read_file(folder / "out/report.json"));
  EXPECT_EQ(report["converged"], true);
  EXPECT_EQ(report["scene"]["name"], "cantilever");
  // The tip bends down by a visible fraction of the length.
  EXPECT_GT(report["results"]["max_displacement"].get<double>(), 0.1);
  EXPECT_TRUE(fs::exists(folder / "out/result.vtu"));
}

// bin/tailor makes OpenBLAS run the kernels of the CPU's instruction set when OpenBLAS fell back to
// older ones (forward/solve/blas_info.hpp): this test process does not, so where it runs
// "Prescott" kernels on a CPU with AVX2 or AVX-512 (a CPU OpenBLAS 0.3.21 does not recognise), the
// executable's report must name the CPU's kernels. A core the user sets is kept.
TEST(Cli, ReportNamesTheBlasKernelsAndTheExecutableUsesTheCpus) {
  const std::string here = blas_core(), cpu = cpu_blas_core();
  if (here.empty()) GTEST_SKIP() << "the BLAS is not OpenBLAS";
  TempFolder folder("problems_cli_blas_core");
  write_file(folder / "box.json", testing::small_box_scene());
  std::string output;
  const std::string scene = (folder / "box.json") + " --out " + (folder / "out");
  ASSERT_EQ(run_cli_with("env -u OPENBLAS_CORETYPE -u TAILOR_BLAS_REEXEC", "simulate " + scene, folder / "log",
                         output),
            0)
      << output;
  const std::string chosen =
      parse_json(read_file(folder / "out/report.json"))["threads"]["blas_core"].get<std::string>();
  if (here == "Prescott" && !cpu.empty())
    EXPECT_EQ(chosen, cpu);
  else
    EXPECT_TRUE(chosen == here || chosen == cpu) << chosen;
  ASSERT_EQ(run_cli_with("env OPENBLAS_CORETYPE=Prescott", "simulate " + scene, folder / "log", output), 0) << output;
  EXPECT_EQ(parse_json(read_file(folder / "out/report.json"))["threads"]["blas_core"].get<std::string>(), "Prescott");
}

TEST(Cli, SceneFileRunsAndChecks) {
  TempFolder folder("problems_cli_scene");
  write_file(folder / "box.json", testing::small_box_scene());
  std::string output;
  EXPECT_EQ(
      run_cli("simulate " + (folder / "box.json") + " --out " + (folder / "out"), folder / "log", output), 0)
      << output;
  EXPECT_TRUE(fs::exists(folder / "out/report.json"));
  EXPECT_EQ(run_cli("check " + (folder / "box.json") + " --seed 7", folder / "log", output), 0) << output;
  EXPECT_NE(output.find("derivative check of 'elastic(linear)'"), std::string::npos) << output;
}

TEST(Cli, UsageVersionAndUnknownInput) {
  TempFolder folder("problems_cli_usage");
  std::string output;
  EXPECT_EQ(run_cli("--version", folder / "log", output), 0);
  EXPECT_EQ(output.rfind("tailor ", 0), 0u) << output;
  EXPECT_EQ(run_cli("--help", folder / "log", output), 0);
  EXPECT_NE(output.find("usage: tailor"), std::string::npos);
  EXPECT_EQ(run_cli("", folder / "log", output), 2);
  EXPECT_EQ(run_cli("frobnicate", folder / "log", output), 2);
  EXPECT_NE(output.find("unknown verb 'frobnicate'"), std::string::npos) << output;
  EXPECT_EQ(run_cli("simulate --fast", folder / "log", output), 2);
  EXPECT_NE(output.find("unknown option '--fast'"), std::string::npos) << output;
  EXPECT_EQ(run_cli("simulate " + (folder / "missing.json"), folder / "log", output), 2);
  EXPECT_NE(output.find("cannot open the scene file"), std::string::npos) << output;
}

}  // namespace
}  // namespace tailor::report_test
