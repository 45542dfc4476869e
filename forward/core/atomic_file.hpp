#pragma once
// Files that a reader sees whole or not at all: the bytes go to a temporary file in the same
// folder (named after the target, this process and a counter), which commit() flushes to the
// disk and renames over the target. A run killed while writing leaves the previous file (or
// none) and a temporary, never a truncated target. Every output file of tailor is written this
// way (reports, checkpoints, .vtu, .pvd, .png; docs/scenes.md).
#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

namespace tailor {

class AtomicFile {
 public:
  // Opens the temporary file. Throws std::runtime_error naming `path` and the reason.
  explicit AtomicFile(std::string path);
  // Without commit() (an exception on the way): removes the temporary; the target is unchanged.
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void write(std::string_view bytes);
  void write(const void* data, std::size_t size);
  // Flushes, syncs and renames the temporary over the target. Throws std::runtime_error naming
  // the target and the first failure's reason (a full disk shows here or in write); the
  // temporary is then removed.
  void commit();
  const std::string& path() const { return path_; }

 private:
  [[noreturn]] void fail(int error);

  std::string path_, temporary_;
  std::FILE* file_ = nullptr;
  int error_ = 0;  // the first failure's errno
};

// `text` written to `path` by an AtomicFile.
void write_text_file_atomically(const std::string& path, std::string_view text);

}  // namespace tailor
