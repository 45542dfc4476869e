// Output files appear whole or not at all (forward/core/atomic_file.hpp): a committed file has
// the bytes written; an abandoned one (an exception before commit) leaves the previous file and
// no temporary; a target in a missing folder fails naming the target.
#include "forward/core/atomic_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "../../support/temp_folder.hpp"
#include "../../support/text_files.hpp"

namespace tailor::atomic_file_test {
namespace {

namespace fs = std::filesystem;

using tailor::testing::read_file;
int entries(const std::string& folder) {
  int n = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(folder)) ++n;
  return n;
}

TEST(AtomicFile, CommitReplacesTheTargetAndAbandoningKeepsIt) {
  testing::TempFolder folder("atomic_file");
  const std::string path = folder / "result.vtu";
  write_text_file_atomically(path, "first");
  EXPECT_EQ(read_file(path), "first");
  {
    AtomicFile file(path);
    file.write("sec");
    file.write(std::string_view("ond"));
    EXPECT_EQ(read_file(path), "first");  // not yet: the bytes are in the temporary
    EXPECT_EQ(entries(folder.str()), 2);
    file.commit();
  }
  EXPECT_EQ(read_file(path), "second");
  EXPECT_EQ(entries(folder.str()), 1);
  try {
    AtomicFile file(path);
    file.write("a truncated thi");
    throw std::runtime_error("killed while writing");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(read_file(path), "second");
  EXPECT_EQ(entries(folder.str()), 1);  // no temporary left
  try {
    AtomicFile file(folder / "missing/result.vtu");
    ADD_FAILURE() << "opened a file in a missing folder";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("missing/result.vtu"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tailor::atomic_file_test
