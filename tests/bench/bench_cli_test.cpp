// The command lines and JSON reports of the programs in bench/ (bench/bench_cli.hpp): --help
// exits with 0, a bad flag value exits with 2 and names the flag before any work starts, and a
// report parses back as JSON even with non-finite numbers and control characters in it.
#include "bench/bench_cli.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "../support/temp_folder.hpp"
#include "../support/text_files.hpp"
#include "problems/json_text.hpp"
#include "tests/support/test_paths.hpp"

namespace tailor::bench_cli_test {
namespace {

using testing::TempFolder;

using tailor::testing::read_file;
// Runs build/bin/<program> with `arguments` in `folder`; returns its exit code, with stdout and
// stderr in `output`.
int run_bench(const std::string& program, const std::string& arguments, const TempFolder& folder,
              std::string& output) {
  const std::string log = folder / (program + ".log");
  const std::string command = "cd " + folder.str() + " && " + std::string(::tailor::testing::binary_dir()) +
                              "/bin/" + program + " " + arguments + " > " + log + " 2>&1";
  const int status = std::system(command.c_str());
  output = read_file(log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

const char* const kBenches[] = {"adjoint_bench",
                                "damping_design_bench",
                                "dynamics_bench",
                                "homogenization_bench",
                                "material_modes_bench",
                                "newton_bench",
                                "recovery_bench",
                                "reduced_dynamics_bench",
                                "reduction_error_bench",
                                "rigid_pile_bench",
                                "rigid_stack_bench",
                                "rod_bench",
                                "solver_defaults_bench",
                                "spline_material_bench"};

TEST(BenchCli, HelpExitsWithZeroAndListsTheFlags) {
  TempFolder folder("bench_cli_help");
  for (const char* program : kBenches) {
    std::string output;
    EXPECT_EQ(run_bench(program, "--help", folder, output), 0) << program << "\n" << output;
    EXPECT_NE(output.find("Usage: " + std::string(program)), std::string::npos) << output;
    EXPECT_NE(output.find("--out"), std::string::npos) << output;
  }
}

TEST(BenchCli, BadValuesExitWithTwoNamingTheFlag) {
  TempFolder folder("bench_cli_bad");
  const struct {
    const char* program;
    const char* arguments;
    const char* message;
  } cases[] = {
      {"adjoint_bench", "--tets 5", "--tets: expected an integer >= 6, got '5'"},
      {"newton_bench", "--tets 1000,abc", "--tets: expected an integer >= 6, got 'abc'"},
      {"spline_material_bench", "--tets 1e5", "--tets: expected an integer >= 6, got '1e5'"},
      {"dynamics_bench", "--steps 0", "--steps: expected an integer >= 1, got '0'"},
      {"dynamics_bench", "--reuse-factorization on", "unexpected argument 'on'"},
      {"damping_design_bench", "--plates 3", "unknown flag '--plates'"},
      {"rigid_pile_bench", "--dt 0.01", "unknown flag '--dt'"},
      {"homogenization_bench", "--n2d 0", "--n2d: expected an integer >= 1, got '0'"},
      {"material_modes_bench", "--time-limit -1", "--time-limit: expected a number >= 0, got '-1'"},
      {"material_modes_bench", "--scenes small,huge", "--scenes: expected one of small, large, got 'huge'"},
      {"material_modes_bench", "--reuse-factorization --no-reuse-factorization",
       "--reuse-factorization excludes --no-reuse-factorization"},
      {"reduced_dynamics_bench", "--ranks 10,0", "--ranks: expected an integer >= 1, got '0'"},
      {"reduction_error_bench", "--time-step 0", "--time-step: expected a number > 0, got '0'"},
      {"reduction_error_bench", "--duration 0.01", "--duration must be at least one --time-step"},
      {"rigid_pile_bench", "--hessian fancy",
       "--hessian: expected one of adaptive, projected, exact, got 'fancy'"},
      {"rigid_pile_bench", "--time-step nan", "--time-step: expected a number > 0, got 'nan'"},
      {"rigid_stack_bench", "--height x", "--height: expected an integer >= 1, got 'x'"},
      {"rod_bench", "--vertices 2", "--vertices: expected an integer >= 3, got '2'"},
      {"solver_defaults_bench", "--repeats", "--repeats"},
      {"recovery_bench", "--size 12k", "--size: expected one of 6k, 48k, got '12k'"},
      {"recovery_bench", "--backends newton_cg,lbfgs", "--backends: unknown optimizer back-end 'lbfgs'"},
      {"recovery_bench", "--reuse maybe", "--reuse: expected one of auto, across, off, got 'maybe'"},
      {"recovery_bench", "--jacobi maybe", "--jacobi: expected one of yes, no, got 'maybe'"},
      {"recovery_bench", "--exact-hessian 1", "--exact-hessian: expected one of yes, no, got '1'"},
      {"recovery_bench", "--per-iteration maybe", "--per-iteration: expected one of yes, no, got 'maybe'"},
      {"recovery_bench", "--cg-resolution -1", "--cg-resolution: expected a number >= 0, got '-1'"},
  };
  for (const auto& c : cases) {
    std::string output;
    EXPECT_EQ(run_bench(c.program, c.arguments, folder, output), 2) << c.program << " " << c.arguments;
    EXPECT_NE(output.find(std::string(c.program) + ": " + c.message), std::string::npos) << output;
  }
}

TEST(BenchCli, AReportStartsWithTheHeaderAndParses) {
  TempFolder folder("bench_cli_report");
  std::string output;
  ASSERT_EQ(run_bench("rod_bench", "--vertices 5,8 --iterations 1 --out rods.json", folder, output), 0)
      << output;
  const auto report = parse_ordered_json(read_file(folder / "rods.json"));
  EXPECT_EQ(report.begin().key(), "tailor_version");
  EXPECT_EQ(report["benchmark"], "rod_newton_iteration");
  EXPECT_TRUE(report["threads"].contains("blas_library"));
  ASSERT_EQ(report["sizes"].size(), 2u);  // the list replaced the default sizes
  EXPECT_EQ(report["sizes"][1]["vertices"], 8);
}

// recovery_bench, cut short: a row per variant (newton_cg twice: its default curvature and the
// exact Hessian), with the counts the table prints.
TEST(BenchCli, RecoveryBenchReportsEveryVariantWithItsCounts) {
  TempFolder folder("bench_cli_recovery");
  std::string output;
  ASSERT_EQ(run_bench("recovery_bench", "--backends newton_cg,nlopt_lbfgs --max-iterations 2 --out r.json", folder,
                      output),
            0)
      << output;
  const auto report = parse_ordered_json(read_file(folder / "r.json"));
  EXPECT_EQ(report["benchmark"], "recovery");
  EXPECT_EQ(report["tets"], 6000);
  ASSERT_EQ(report["rows"].size(), 3u) << output;
  EXPECT_EQ(report["rows"][0]["curvature"], "automatic");
  EXPECT_EQ(report["rows"][1]["curvature"], "exact");
  for (const auto& row : report["rows"]) {
    EXPECT_GT(row["factorizations"].get<long>(), 0) << row.dump();
    EXPECT_GT(row["back_solves"].get<long>(), 0) << row.dump();
  }
  EXPECT_GT(report["rows"][0]["hessian_vectors"].get<int>(), 0);
  EXPECT_EQ(report["rows"][2]["hessian_vectors"].get<int>(), 0);
}

// Written by write_report: +-inf and NaN become null, control characters are escaped.
TEST(BenchCli, NonFiniteNumbersAndControlCharactersStayValidJson) {
  TempFolder folder("bench_cli_json");
  bench::Json report = bench::report("json_test");
  report["infinite"] = std::numeric_limits<double>::infinity();
  report["values"] =
      bench::array(std::vector<double>{1.5, -std::numeric_limits<double>::infinity(), std::nan("")});
  report["label"] = std::string("tab\there, bell \a, quote \" and newline\n");
  ASSERT_TRUE(bench::write_report(folder / "report.json", report, "bench_cli_test"));
  const std::string text = read_file(folder / "report.json");
  const auto parsed = parse_json(text);
  EXPECT_TRUE(parsed["infinite"].is_null());
  EXPECT_EQ(parsed["values"][0], 1.5);
  EXPECT_TRUE(parsed["values"][1].is_null());
  EXPECT_TRUE(parsed["values"][2].is_null());
  EXPECT_EQ(parsed["label"], "tab\there, bell \a, quote \" and newline\n");
  EXPECT_NE(text.find("\\u0007"), std::string::npos) << text;
  EXPECT_EQ(parsed["benchmark"], "json_test");

  EXPECT_FALSE(bench::write_report(folder / "missing/folder/report.json", report, "bench_cli_test"));
}

}  // namespace
}  // namespace tailor::bench_cli_test
