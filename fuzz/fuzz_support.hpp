#pragma once
// Shared by the fuzz targets (docs/testing.md): what counts as a clean rejection of bad input,
// and the input as a file for the readers that take a path.
//
// A reader may refuse any input, but only with SceneError, MeshError or std::invalid_argument
// carrying a message. Anything else -- a sanitizer report, a crash, another exception type
// (std::bad_alloc from an absurd size included), a hang -- is a finding: libFuzzer stops and
// saves the input.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "forward/mesh/mesh.hpp"
#include "problems/scene_error.hpp"  // header-only, so the mesh targets need not link problems/

namespace tailor::fuzz {

// The folder relative paths in fuzzed scenes resolve against (the shipped scenes' folder).
inline const std::string kScenesDir = TAILOR_FUZZ_SCENES_DIR;

[[noreturn]] inline void empty_message(const char* type) {
  std::fprintf(stderr, "fuzz: %s without a message\n", type);
  std::abort();
}

// Runs `read`; a clean rejection ends it quietly, anything else escapes to libFuzzer.
template <class Read>
void expect_clean(Read&& read) {
  try {
    read();
  } catch (const SceneError& e) {
    if (*e.what() == '\0') empty_message("SceneError");
  } catch (const MeshError& e) {
    if (*e.what() == '\0') empty_message("MeshError");
  } catch (const std::invalid_argument& e) {
    if (*e.what() == '\0') empty_message("std::invalid_argument");
  }
}

inline std::string as_text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// A scratch folder of this process (libFuzzer's -jobs and -fork run several), removed at exit.
// The path is never destroyed, so the exit handler can still read it.
inline const std::filesystem::path& scratch_folder() {
  static const std::filesystem::path* folder = [] {
    const std::filesystem::path base =
        std::filesystem::exists("/dev/shm") ? "/dev/shm" : std::filesystem::temp_directory_path();
    auto* f = new std::filesystem::path(base / ("tailor_fuzz_" + std::to_string(::getpid())));
    std::filesystem::create_directories(*f);
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(scratch_folder(), ignored);
    });
    return f;
  }();
  return *folder;
}

// Writes `text` to scratch_folder()/name and returns the path.
inline std::string write_input(const std::string& name, const std::string& text) {
  const std::string path = (scratch_folder() / name).string();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.close();
  if (!out) {
    std::fprintf(stderr, "fuzz: cannot write %s\n", path.c_str());
    std::abort();
  }
  return path;
}

}  // namespace tailor::fuzz
