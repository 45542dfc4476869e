// Long runs survive a kill: `tailor run` writes DIR/checkpoint.json every K iterations; a run
// killed with SIGKILL mid-way and continued with `tailor run --resume DIR` reaches the same
// design as an uninterrupted run, having lost at most K iterations. Also the flags' errors.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "../support/temp_folder.hpp"
#include "../support/text_files.hpp"
#include "tests/support/test_paths.hpp"

extern char** environ;

namespace tailor::resume_cli_test {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using TempFolder = tailor::testing::TempFolder;

const std::string kTailor = std::string(::tailor::testing::binary_dir()) + "/bin/tailor";

using tailor::testing::read_file;
Json read_json(const std::string& path) { return Json::parse(read_file(path)); }

// Starts bin/tailor with `arguments`, stdout and stderr into `log`.
pid_t spawn_tailor(const std::vector<std::string>& arguments, const std::string& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  std::vector<std::string> words{kTailor};
  words.insert(words.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int error = posix_spawn(&pid, kTailor.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return error == 0 ? pid : -1;
}

// Runs bin/tailor to the end; its exit code (-1 when it did not exit normally).
int run_tailor(const std::vector<std::string>& arguments, const std::string& log) {
  const pid_t pid = spawn_tailor(arguments, log);
  int status = 0;
  if (pid < 0 || waitpid(pid, &status, 0) != pid) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The last iteration of the progress table in a log (-1 when none).
int last_printed_iteration(const std::string& log) {
  static const std::regex row(R"(^\s*(\d+)\s+[-+0-9.e]+\s+[-+0-9.e]+\s+[-+0-9.e]+\s+[0-9.]+\s+\d+\s+\d+$)");
  int last = -1;
  std::istringstream lines(read_file(log));
  std::smatch match;
  for (std::string line; std::getline(lines, line);)
    if (std::regex_match(line, match, row)) last = std::stoi(match[1]);
  return last;
}

// A 2D plate of two neo-Hookean halves pulled along x; both moduli (truth 2e5, noisy
// observations of every vertex) start at 1e5. Projected gradient descent converges in about 70
// iterations of some milliseconds each (22 x 11 cells keep each material's elements below the
// threshold where assembly goes parallel, which a loaded machine makes slow), so a kill right
// after the first checkpoint lands mid-way.
std::string plate_scene(const std::string& optimizer) {
  return R"({
  "name": "tension_plate",
  "mesh": {"rectangle": {"min": [0, 0], "max": [2, 1], "cells": [22, 11]}},
  "materials": [
    {"elements": {"box": {"min": [0, 0], "max": [1, 1]}}, "model": "neo_hookean", "youngs_modulus": 1e5, "poisson_ratio": 0.3},
    {"elements": {"box": {"min": [1, 0], "max": [2, 1]}}, "model": "neo_hookean", "youngs_modulus": 1e5, "poisson_ratio": 0.3}
  ],
  "dirichlet": [{"vertices": {"plane": {"axis": "x", "value": 0}}}],
  "loads": {"tractions": [{"faces": {"plane": {"axis": "x", "value": 2}}, "traction": [5000, 0]}]},
  "inverse": {
    "design": {"parameter": "youngs_modulus", "granularity": "per_material", "min": 1e3, "max": 1e8},
    "objective": [
      {"type": "synthetic_observations", "vertices": {"box": {"min": [0, 0], "max": [2, 1]}},
       "youngs_modulus": {"materials": [2e5, 2e5]}, "noise": 1e-3, "seed": 1}
    ],
    "optimizer": )" +
         optimizer + R"(
  }
})";
}

const char* const kGradientDescent =
    R"({"backend": "gradient_descent", "max_iterations": 1000, "gradient_tolerance": 1e-9})";

TEST(ResumeCli, ARunKilledMidWayResumesToTheSameDesign) {
  TempFolder folder("resume_cli_kill");
  const std::string scene = folder / "plate.json";
  std::ofstream(scene) << plate_scene(kGradientDescent);
  const int k = 10;
  const std::string every = std::to_string(k);

  // The uninterrupted run.
  ASSERT_EQ(run_tailor({"run", scene, "--quiet", "--checkpoint-every", every, "--out", folder / "whole"},
                       folder / "whole.log"),
            0)
      << read_file(folder / "whole.log");
  const Json whole = read_json(folder / "whole/report.json");

  // The same run, killed between its first and its second checkpoint: once the first is there
  // and the progress table has gone half-way to the next.
  const std::string killed_dir = folder / "killed";
  const pid_t pid =
      spawn_tailor({"run", scene, "--checkpoint-every", every, "--out", killed_dir}, folder / "killed.log");
  ASSERT_GT(pid, 0);
  const std::string checkpoint = killed_dir + "/checkpoint.json";
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!(fs::exists(checkpoint) && last_printed_iteration(folder / "killed.log") >= k + k / 2) &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL)
      << "the run ended before the kill (make it longer): " << read_file(folder / "killed.log");
  ASSERT_TRUE(fs::exists(checkpoint)) << read_file(folder / "killed.log");
  EXPECT_FALSE(fs::exists(killed_dir + "/report.json"));  // it did not get to the end

  // Lost: the iterations done after the last checkpoint.
  const int checkpointed = read_json(checkpoint)["iteration"].get<int>();
  const int printed = last_printed_iteration(folder / "killed.log");
  EXPECT_GE(checkpointed, k);
  EXPECT_GE(printed, checkpointed);
  EXPECT_LE(printed - checkpointed, k);

  // Resumed, it ends where the uninterrupted run did.
  ASSERT_EQ(
      run_tailor({"run", scene, "--resume", killed_dir, "--checkpoint-every", every}, folder / "resumed.log"),
      0)
      << read_file(folder / "resumed.log");
  const std::string resumed_log = read_file(folder / "resumed.log");
  EXPECT_NE(resumed_log.find("resuming from " + checkpoint + " at iteration " + std::to_string(checkpointed)),
            std::string::npos)
      << resumed_log;
  EXPECT_NE(
      resumed_log.find("resumed        : from the checkpoint at iteration " + std::to_string(checkpointed)),
      std::string::npos)
      << resumed_log;
  const Json resumed = read_json(killed_dir + "/report.json");
  ASSERT_FALSE(resumed["resumed"].is_null());
  EXPECT_EQ(resumed["resumed"]["iteration"].get<int>(), checkpointed);
  EXPECT_EQ(resumed["resumed"]["checkpoint"].get<std::string>(), checkpoint);
  EXPECT_EQ(resumed["status"], "converged");
  // The history goes on from the checkpoint: one row per iteration, the first ones its own.
  const Json& history = resumed["history"];
  ASSERT_EQ(history.size(), resumed["iterations"].get<std::size_t>() + 1);
  for (std::size_t i = 0; i < history.size(); ++i) EXPECT_EQ(history[i]["iteration"].get<std::size_t>(), i);
  EXPECT_EQ(history[0]["objective"], whole["history"][0]["objective"]);

  // The same design to the Newton tolerance: gradient_descent takes its whole state back
  // (iterate and step length); only the forward solves restart from rest instead of the last
  // equilibrium. So the same number of iterations too.
  const int whole_iterations = whole["iterations"].get<int>();
  const int resumed_iterations = resumed["iterations"].get<int>();
  const double whole_objective = whole["objective"]["final"].get<double>();
  const double resumed_objective = resumed["objective"]["final"].get<double>();
  std::cout << "uninterrupted: " << whole_iterations << " iterations, J = " << whole_objective
            << "; killed after iteration " << printed << ", checkpoint at " << checkpointed << " (lost "
            << printed - checkpointed << "); resumed: " << resumed_iterations
            << " iterations, J = " << resumed_objective
            << ", |dJ| / J = " << std::abs(resumed_objective - whole_objective) / whole_objective << "\n";
  EXPECT_NEAR(resumed_iterations, whole_iterations, 2);
  EXPECT_LE(std::abs(resumed_objective - whole_objective), 1e-6 * whole_objective);
  const Json& a = whole["design"]["values"];
  const Json& b = resumed["design"]["values"];
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    EXPECT_NEAR(b[i].get<double>(), a[i].get<double>(), 1e-6 * a[i].get<double>()) << i;
}

TEST(ResumeCli, ACheckpointOfAnotherSceneOrAMissingOneExitsWithTwo) {
  TempFolder folder("resume_cli_errors");
  const std::string scene = folder / "plate.json";
  std::ofstream(scene) << plate_scene(R"({"backend": "gradient_descent", "max_iterations": 3})");
  ASSERT_EQ(
      run_tailor({"run", scene, "--quiet", "--checkpoint-every", "2", "--out", folder / "a"}, folder / "log"),
      1)
      << read_file(folder / "log");  // max_iterations: not converged
  ASSERT_TRUE(fs::exists(folder / "a/checkpoint.json"));
  EXPECT_EQ(read_json(folder / "a/checkpoint.json")["iteration"], 3);  // the final one

  // Another back-end, another design size, no checkpoint at all.
  std::ofstream(folder / "lbfgs.json") << plate_scene(R"({"backend": "nlopt_lbfgs"})");
  EXPECT_EQ(run_tailor({"run", folder / "lbfgs.json", "--resume", folder / "a"}, folder / "log"), 2);
  EXPECT_NE(read_file(folder / "log").find("the checkpoint belongs to another run"), std::string::npos)
      << read_file(folder / "log");
  EXPECT_NE(read_file(folder / "log").find("back-end 'gradient_descent' (this run: 'nlopt_lbfgs')"),
            std::string::npos);
  std::string per_element = plate_scene(R"({"backend": "gradient_descent"})");
  per_element.replace(per_element.find("per_material"), 12, "per_element");
  std::ofstream(folder / "element.json") << per_element;
  EXPECT_EQ(run_tailor({"run", folder / "element.json", "--resume", folder / "a"}, folder / "log"), 2);
  EXPECT_NE(read_file(folder / "log").find("design size '2' (this run: '"), std::string::npos)
      << read_file(folder / "log");
  EXPECT_EQ(run_tailor({"run", scene, "--resume", folder / "nowhere"}, folder / "log"), 2);
  EXPECT_NE(read_file(folder / "log").find("nowhere: cannot open the checkpoint"), std::string::npos)
      << read_file(folder / "log");
  EXPECT_EQ(run_tailor({"run", scene, "--checkpoint-every", "-1"}, folder / "log"), 2);
  EXPECT_NE(read_file(folder / "log")
                .find("--checkpoint-every: expected an integer from 0 to 1000000000, got '-1'"),
            std::string::npos);
  EXPECT_EQ(run_tailor({"simulate", scene, "--resume", folder / "a"}, folder / "log"), 2);
  EXPECT_NE(read_file(folder / "log").find("unknown option '--resume' for 'simulate'"), std::string::npos);

  // --checkpoint-every 0: no checkpoint.
  ASSERT_EQ(
      run_tailor({"run", scene, "--quiet", "--checkpoint-every", "0", "--out", folder / "b"}, folder / "log"),
      1);
  EXPECT_TRUE(fs::exists(folder / "b/report.json"));
  EXPECT_FALSE(fs::exists(folder / "b/checkpoint.json"));
}

}  // namespace
}  // namespace tailor::resume_cli_test
