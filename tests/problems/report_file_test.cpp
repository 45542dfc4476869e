// Every kind's report.json goes through problems/report_file.hpp: the common header first, the
// report's own fields in their order, and an atomic write (a reader sees the old file or the
// new one; a failed write leaves the old one and no temporary file behind).
#include "problems/report_file.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "../support/report_checks.hpp"
#include "../support/temp_folder.hpp"
#include "../support/text_files.hpp"
#include "problems/json_text.hpp"

namespace tailor::report_file_test {
namespace {

namespace fs = std::filesystem;
using testing::TempFolder;

using tailor::testing::read_file;
// The names in `folder`.
std::vector<std::string> listing(const std::string& folder) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(ReportFile, TheHeaderComesFirstAndTheReportKeepsItsOrder) {
  const TempFolder folder("report_file_header");
  nlohmann::ordered_json report;
  report["status"] = "ok";
  report["zeta"] = 1;
  report["alpha"] = {1, 2};
  const std::string path = write_report(folder / "out/nested", report);  // the folder is made
  EXPECT_EQ(path, folder / "out/nested/report.json");
  testing::expect_report_header(path);
  const nlohmann::ordered_json written = parse_ordered_json(read_file(path));
  std::vector<std::string> keys;
  for (const auto& item : written.items()) keys.push_back(item.key());
  EXPECT_EQ(keys, (std::vector<std::string>{"tailor_version", "report_format", "threads", "status", "zeta",
                                            "alpha"}));
  EXPECT_EQ(read_file(path), dump_json(written, 2) + "\n");  // indented by 2, one final newline

  // A report that starts with the header is written as it is, the header's values included.
  nlohmann::ordered_json own = written;
  own["report_format"] = 99;
  write_report_file(path, own);
  EXPECT_EQ(parse_ordered_json(read_file(path))["report_format"], 99);
  EXPECT_EQ(listing(folder / "out/nested"), std::vector<std::string>{"report.json"});
}

TEST(ReportFile, AFailedWriteLeavesThePreviousReportAndNoTemporaryFile) {
  const TempFolder folder("report_file_failure");
  nlohmann::ordered_json report = {{"status", "first"}};
  const std::string path = write_report(folder.str(), report);
  const std::string before = read_file(path);
  // A report that cannot be serialized (not UTF-8): nothing is written.
  report["status"] = std::string("\xff\xfe");
  EXPECT_THROW(write_report(folder.str(), report), nlohmann::json::type_error);
  EXPECT_EQ(read_file(path), before);
  EXPECT_EQ(listing(folder.str()), std::vector<std::string>{"report.json"});
  // The rename fails (the target is a folder with something in it): the temporary is removed and
  // the error names the target.
  fs::create_directories(folder / "blocked/report.json/inside");
  try {
    write_report(folder / "blocked", {{"status", "second"}});
    ADD_FAILURE() << "the write did not fail";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("cannot write '" + (folder / "blocked/report.json") + "': ", 0), 0u)
        << e.what();
  }
  EXPECT_EQ(listing(folder / "blocked"), std::vector<std::string>{"report.json"});
  // The temporary cannot be made (no such folder): the error names the target.
  try {
    write_text_file_atomically(folder / "missing/notes.txt", "text");
    ADD_FAILURE() << "the write did not fail";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("cannot write '" + (folder / "missing/notes.txt") + "': ", 0), 0u)
        << e.what();
  }
}

TEST(ReportFile, TextFilesAreReplacedWhole) {
  const TempFolder folder("report_file_text");
  const std::string path = folder / "notes.txt";
  write_text_file_atomically(path, "a longer first version\n");
  write_text_file_atomically(path, "second\n");
  EXPECT_EQ(read_file(path), "second\n");
  EXPECT_EQ(listing(folder.str()), std::vector<std::string>{"notes.txt"});
}

}  // namespace
}  // namespace tailor::report_file_test
