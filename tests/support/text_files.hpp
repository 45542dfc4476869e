#pragma once
// Whole text files for tests: the content of a file ("" when it cannot be read), and a file
// written with a text.
#include <fstream>
#include <iterator>
#include <string>

namespace tailor::testing {

inline std::string read_file(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline void write_file(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

}  // namespace tailor::testing
