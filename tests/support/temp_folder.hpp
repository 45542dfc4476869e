#pragma once
// A fresh scratch folder for one test (named by a tag and the process id so parallel ctest
// runs do not collide), removed afterwards.
#include <unistd.h>

#include <filesystem>
#include <string>

namespace tailor::testing {

class TempFolder {
 public:
  explicit TempFolder(const std::string& tag)
      : path_(std::filesystem::temp_directory_path() / ("tailor_" + tag + "_" + std::to_string(::getpid()))) {
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
inline const std::string kScenesDir = std::string(TAILOR_TEST_DATA_DIR) + "/../../scenes";

}  // namespace tailor::testing
