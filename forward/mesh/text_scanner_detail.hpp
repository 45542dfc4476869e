#pragma once
// Private helper of the mesh readers: a line-by-line scanner over a whole text file that
// parses numbers without allocating and reports every problem as "path:line: what".
//
// The file is read into memory at once; a 200k-tetrahedron mesh is a few megabytes, and
// scanning a buffer with std::from_chars is much faster than stream extraction.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "forward/mesh/mesh.hpp"

namespace tailor::mesh_detail {

inline std::string quoted_token(std::string_view token) {
  constexpr std::size_t kMaxShown = 40;  // a binary blob must not flood the message
  std::string shown(token.substr(0, kMaxShown));
  if (token.size() > kMaxShown) shown += "...";
  return "'" + shown + "'";
}

inline std::string read_whole_file(const std::string& path) {
  // Opening a directory succeeds on some systems and then reads as an empty file.
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored))
    throw MeshError(path + ": is a directory, not a mesh file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MeshError(path + ": cannot open file for reading");
  std::ostringstream contents;
  contents << in.rdbuf();
  if (in.bad()) throw MeshError(path + ": error while reading file");
  return std::move(contents).str();
}

class TextScanner {
 public:
  // `comment` starts a comment that runs to the end of the line ('\0' for none).
  explicit TextScanner(std::string path, char comment = '\0')
      : path_(std::move(path)), text_(read_whole_file(path_)), comment_(comment) {}

  const std::string& path() const { return path_; }
  int line_number() const { return line_number_; }
  std::string_view line() const { return line_; }

  // Moves to the next line (blank or not); false at the end of the file.
  bool next_line() {
    if (next_start_ >= text_.size()) {
      line_ = {};
      cursor_ = 0;
      return false;
    }
    std::size_t end = text_.find('\n', next_start_);
    if (end == std::string::npos) end = text_.size();
    line_ = std::string_view(text_).substr(next_start_, end - next_start_);
    if (comment_ != '\0') line_ = line_.substr(0, line_.find(comment_));
    if (!line_.empty() && line_.back() == '\r') line_.remove_suffix(1);
    next_start_ = end + 1;
    ++line_number_;
    cursor_ = 0;
    return true;
  }

  // Moves to the next line holding at least one token; false at the end of the file.
  bool next_data_line() {
    while (next_line()) {
      if (!at_line_end()) return true;
    }
    return false;
  }

  // Like next_data_line, but the end of the file is an error while reading `what` (its
  // record `record` of `count`, when given). Labels are string views and messages are only
  // built on failure, so that reading a line allocates nothing.
  void require_data_line(std::string_view what, std::int64_t record = 0, std::int64_t count = 0) {
    if (next_data_line()) return;
    std::string label(what);
    if (record > 0) label += " " + std::to_string(record) + " of " + std::to_string(count);
    fail_eof(label);
  }

  // How many of `count` records of `tokens` tokens each the rest of the file can hold (a token
  // takes at least one character and one separator): what a reader may reserve for a record
  // count read from the file, so that a header announcing 10^8 records in a file of a few
  // bytes cannot make it allocate gigabytes before the records run out.
  std::size_t records_that_fit(std::int64_t count, int tokens) const {
    const std::size_t remaining = text_.size() - std::min(next_start_, text_.size());
    const auto fit = static_cast<std::int64_t>(remaining / (2 * static_cast<std::size_t>(tokens)) + 1);
    return static_cast<std::size_t>(std::max<std::int64_t>(0, std::min(count, fit)));
  }

  bool at_line_end() {
    skip_blanks();
    return cursor_ >= line_.size();
  }

  // The next whitespace-separated token of the current line; false when there is none.
  bool next_token(std::string_view& token) {
    skip_blanks();
    if (cursor_ >= line_.size()) return false;
    const std::size_t begin = cursor_;
    while (cursor_ < line_.size() && !is_blank(line_[cursor_])) ++cursor_;
    token = line_.substr(begin, cursor_ - begin);
    return true;
  }

  std::string_view token(std::string_view what) {
    std::string_view t;
    if (!next_token(t)) {
      // A record cut short by the end of the file is a truncated file, not a bad line.
      fail("expected " + std::string(what) + ", but the line ends" +
           (next_start_ >= text_.size() ? " (and so does the file: is it truncated?)" : ""));
    }
    return t;
  }

  std::int64_t read_int(std::string_view what) {
    const std::string_view t = token(what);
    std::int64_t value = 0;
    const char* first = t.data();
    if (t.size() > 1 && t[0] == '+') ++first;  // from_chars does not accept a leading '+'
    const auto [ptr, ec] = std::from_chars(first, t.data() + t.size(), value);
    if (ec == std::errc::result_out_of_range)
      fail(std::string(what) + " " + quoted_token(t) + " is out of range");
    if (ec != std::errc() || ptr != t.data() + t.size()) {
      fail("expected " + std::string(what) + " (an integer), found " + quoted_token(t));
    }
    return value;
  }

  // An integer that must fit an int and lie in [lo, hi].
  int read_int_in(std::string_view what, std::int64_t lo, std::int64_t hi) {
    const std::int64_t value = read_int(what);
    if (value < lo || value > hi) {
      fail(std::string(what) + " is " + std::to_string(value) + ", expected a value in [" +
           std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    return static_cast<int>(value);
  }

  // Any floating-point number, including nan and inf (the caller decides what is allowed).
  double read_double(std::string_view what) {
    const std::string_view t = token(what);
    double value = 0.0;
    const char* first = t.data();
    if (t.size() > 1 && t[0] == '+') ++first;
    const auto [ptr, ec] = std::from_chars(first, t.data() + t.size(), value);
    // from_chars leaves `value` untouched when out of range; strtod tells an overflow
    // (+-HUGE_VAL, reported as non-finite by the caller) from an underflow (about zero).
    if (ec == std::errc::result_out_of_range) return std::strtod(std::string(t).c_str(), nullptr);
    if (ec != std::errc() || ptr != t.data() + t.size()) {
      fail("expected " + std::string(what) + " (a number), found " + quoted_token(t));
    }
    return value;
  }

  double read_finite(std::string_view what) {
    const double value = read_double(what);
    if (!std::isfinite(value)) fail(std::string(what) + " is not a finite number");
    return value;
  }

  void expect_line_end(std::string_view record) {
    std::string_view extra;
    if (next_token(extra)) {
      fail("unexpected extra text " + quoted_token(extra) + " after " + std::string(record));
    }
  }

  // "path:line", or only the path before the first line (an empty file).
  std::string location() const {
    return line_number_ > 0 ? path_ + ":" + std::to_string(line_number_) : path_;
  }

  [[noreturn]] void fail(const std::string& what) const { throw MeshError(location() + ": " + what); }

  [[noreturn]] void fail_eof(std::string_view what) const {
    throw MeshError(location() + ": unexpected end of file while reading " + std::string(what));
  }

 private:
  static bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
  void skip_blanks() {
    while (cursor_ < line_.size() && is_blank(line_[cursor_])) ++cursor_;
  }

  std::string path_;
  std::string text_;
  char comment_;
  std::size_t next_start_ = 0;
  int line_number_ = 0;
  std::string_view line_;
  std::size_t cursor_ = 0;
};

// What a reader collected before it becomes a Mesh: flat arrays plus the source line of each
// element, so validation errors can point at the line to fix.
struct RawMesh {
  int dim = 0;
  std::vector<double> coordinates;  // num_vertices * dim
  std::vector<int> elements;        // num_elements * (dim + 1), 0-based
  std::vector<int> regions;         // num_elements
  std::vector<int> element_lines;   // num_elements
};

// A file with triangles but no tetrahedra is read with 3 coordinates per vertex; this makes
// it a 2D mesh by dropping z, after checking that the used vertices lie in one plane z = c
// (a curved surface mesh cannot be a 2D mesh). Expects raw.dim == 3 and 3 vertices per element.
void flatten_triangles(RawMesh& raw, const std::string& path);

// Turns vertex numbers counted from `base` (1 for Medit, 0 or 1 for TetGen) into 0-based
// raw.elements, failing with the element's line when a number is out of range. Elements
// are called "element <e + base>" in messages, as the formats number them.
void set_elements_from_numbers(RawMesh& raw, const std::vector<std::int64_t>& numbers,
                               int vertices_per_element, int base, const std::string& path);

// Builds the Mesh and validates it, naming the file and the element's line on failure.
Mesh finish_mesh(const RawMesh& raw, const std::string& path);

// validate_mesh with, when given, the source line of each element in messages.
void validate_mesh_with_lines(const Mesh& mesh, const std::string& source,
                              const std::vector<int>* element_lines);

}  // namespace tailor::mesh_detail
