#pragma once
// Scratch folders for tests, named so that tests running in parallel never share one.
#include <unistd.h>

#include <filesystem>
#include <string>
#include "tests/support/test_paths.hpp"

namespace tailor::testing {

// A path in the temporary folder that no other test process uses at the same time: ctest runs each
// test in a process of its own, in parallel, so the name carries the process id. Not created.
inline std::filesystem::path unique_temp_path(const std::string& name) {
  return std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
}

class TempFolder {
 public:
  explicit TempFolder(const std::string& tag) : path_(unique_temp_path("tailor_" + tag)) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempFolder() { std::filesystem::remove_all(path_); }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }
  std::string str() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

// The example scenes shipped in scenes/.
inline const std::string kScenesDir = std::string(::tailor::testing::test_data_dir()) + "/../../scenes";

}  // namespace tailor::testing
