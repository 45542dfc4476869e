// The `tailor gradcheck` and `tailor run` verbs of the executable: exit codes, outputs, and
// the progress table that --quiet suppresses.
#include <gtest/gtest.h>

#include "../support/temp_folder.hpp"
#include "../support/text_files.hpp"
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include "tests/support/test_paths.hpp"

namespace tailor::inverse_cli_test {
namespace {

namespace fs = std::filesystem;

const std::string kScenes = tailor::testing::kScenesDir;
const std::string kBar = kScenes + "/two_material_bar_inverse.json";

using TempFolder = tailor::testing::TempFolder;

using tailor::testing::read_file;
// Runs the tailor executable; returns its exit code, with stdout and stderr in `output`.
int run_cli(const std::string& arguments, const std::string& log, std::string& output) {
  const std::string command =
      std::string(::tailor::testing::binary_dir()) + "/bin/tailor " + arguments + " > " + log + " 2>&1";
  const int status = std::system(command.c_str());
  output = read_file(log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Lines of the optimizer's progress table: the header and one row per iteration.
int progress_lines(const std::string& output) {
  static const std::regex row(R"(^\s*\d+\s+[-+0-9.e]+\s+[-+0-9.e]+\s+[-+0-9.e]+\s+[0-9.]+\s+\d+\s+\d+$)");
  int count = 0;
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);)
    if (std::regex_match(line, row) || line.find("|proj g|") != std::string::npos) ++count;
  return count;
}

TEST(InverseCli, GradcheckPassesOnTheExampleAndWritesJson) {
  TempFolder folder("inverse_cli_gradcheck");
  std::string output;
  EXPECT_EQ(run_cli("gradcheck " + kBar + " --out " + (folder / "out") + " --seed 3 --hessian",
                    folder / "log", output),
            0)
      << output;
  EXPECT_NE(output.find("Taylor test"), std::string::npos) << output;
  EXPECT_NE(output.find("passed"), std::string::npos) << output;
  const std::string json = read_file(folder / "out/gradcheck.json");
  EXPECT_NE(json.find("\"seed\": 3"), std::string::npos) << json;
  EXPECT_NE(json.find("\"hessian\""), std::string::npos) << json;
}

TEST(InverseCli, BadInputExitsWithTwo) {
  TempFolder folder("inverse_cli_bad");
  std::string scene = read_file(kBar);
  scene.replace(scene.find("\"granularity\": \"per_material\""), 29, "\"granularity\": \"per_part\"");
  std::ofstream(folder / "bad.json") << scene;
  std::string output;
  EXPECT_EQ(
      run_cli("gradcheck " + (folder / "bad.json") + " --out " + (folder / "out"), folder / "log", output),
      2);
  EXPECT_NE(output.find("bad.json: inverse.design.granularity: expected one of per_element, per_region, "
                        "per_material, modes, got \"per_part\""),
            std::string::npos)
      << output;
  EXPECT_FALSE(fs::exists(folder / "out/gradcheck.json"));

  // A scene without an inverse section, no scene at all, and options of other verbs.
  EXPECT_EQ(run_cli("run " + kScenes + "/cantilever.json --out " + (folder / "out"), folder / "log", output),
            2);
  EXPECT_NE(output.find("no \"inverse\" section"), std::string::npos) << output;
  EXPECT_EQ(run_cli("gradcheck", folder / "log", output), 2);
  EXPECT_NE(output.find("'gradcheck' needs a scene file"), std::string::npos) << output;
  EXPECT_EQ(run_cli("run " + kBar + " --hessian", folder / "log", output), 2);
  EXPECT_NE(output.find("unknown option '--hessian' for 'run'"), std::string::npos) << output;
}

TEST(InverseCli, RunPrintsProgressUnlessQuiet) {
  TempFolder folder("inverse_cli_run");
  std::string output;
  ASSERT_EQ(run_cli("run " + kBar + " --out " + (folder / "loud"), folder / "log", output), 0) << output;
  EXPECT_GT(progress_lines(output), 5) << output;
  EXPECT_NE(output.find("materials[1]: E = "), std::string::npos) << output;
  EXPECT_TRUE(fs::exists(folder / "loud/report.json"));

  ASSERT_EQ(run_cli("run " + kBar + " --quiet --out " + (folder / "quiet"), folder / "log", output), 0)
      << output;
  EXPECT_EQ(progress_lines(output), 0) << output;
  EXPECT_NE(output.find("converged"), std::string::npos) << output;  // the summary stays
  EXPECT_TRUE(fs::exists(folder / "quiet/report.json"));
  EXPECT_TRUE(fs::exists(folder / "quiet/result.vtu"));
}

TEST(InverseCli, UsageListsTheInverseVerbs) {
  TempFolder folder("inverse_cli_usage");
  std::string output;
  EXPECT_EQ(run_cli("--help", folder / "log", output), 0);
  EXPECT_NE(output.find("gradcheck scene.json [--out DIR] [--seed N] [--hessian]"), std::string::npos)
      << output;
  EXPECT_NE(output.find("run scene.json [--out DIR] [--quiet]"), std::string::npos) << output;
}

}  // namespace
}  // namespace tailor::inverse_cli_test
