// Medit .mesh reader (ASCII).
//
// A file is a sequence of keywords; most are followed by a count (on the same line or the
// next) and that many records, one per line. Vertices, Tetrahedra and Triangles are read;
// other sections are skipped record by record, so their layout need not be known.
#include <algorithm>
#include <cctype>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "forward/mesh/mesh_io.hpp"
#include "forward/mesh/text_scanner_detail.hpp"

namespace tailor {
namespace {

using mesh_detail::RawMesh;
using mesh_detail::TextScanner;

bool same_keyword(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

struct MeditElements {
  std::vector<std::int64_t> numbers;  // 1-based vertex numbers
  std::vector<int> refs;
  std::vector<int> lines;
  bool seen = false;
};

class MeditReader {
 public:
  explicit MeditReader(const std::string& path) : in_(path, '#') {}

  Mesh read() {
    while (in_.next_data_line()) {
      const std::string keyword(in_.token("keyword"));
      if (same_keyword(keyword, "End")) break;
      if (same_keyword(keyword, "MeshVersionFormatted")) {
        keyword_value("the format version");
      } else if (same_keyword(keyword, "Dimension")) {
        if (dim_ != 0) in_.fail("Dimension is given twice");
        const std::int64_t dim = keyword_value("the dimension");
        if (dim != 2 && dim != 3) in_.fail("Dimension is " + std::to_string(dim) + ", expected 2 or 3");
        dim_ = static_cast<int>(dim);
      } else if (same_keyword(keyword, "Vertices")) {
        read_vertices();
      } else if (same_keyword(keyword, "Tetrahedra")) {
        read_elements(tets_, 4, "Tetrahedra");
      } else if (same_keyword(keyword, "Triangles")) {
        read_elements(triangles_, 3, "Triangles");
      } else {
        skip_records(keyword);
      }
    }
    return assemble();
  }

 private:
  // The value after a keyword, on the same line or the next.
  std::int64_t keyword_value(const std::string& what) {
    if (in_.at_line_end()) in_.require_data_line(what);
    const std::int64_t value = in_.read_int(what);
    in_.expect_line_end(what);
    return value;
  }

  int record_count(const std::string& keyword) {
    const std::int64_t count = keyword_value("the number of " + keyword);
    if (count < 0 || count > std::numeric_limits<int>::max() / 8) {
      in_.fail("the number of " + keyword + " is " + std::to_string(count));
    }
    return static_cast<int>(count);
  }

  void read_vertices() {
    if (dim_ == 0) in_.fail("Vertices come before Dimension, so their number of coordinates is unknown");
    if (seen_vertices_) in_.fail("a second Vertices section is not supported");
    seen_vertices_ = true;
    const int count = record_count("Vertices");
    coordinates_.reserve(in_.records_that_fit(count, dim_ + 1) * static_cast<std::size_t>(dim_));
    for (int i = 0; i < count; ++i) {
      in_.require_data_line("Vertices", i + 1, count);
      for (int k = 0; k < dim_; ++k) coordinates_.push_back(in_.read_finite("vertex coordinate"));
      in_.read_int("vertex reference");
      in_.expect_line_end("the vertex reference");
    }
  }

  void read_elements(MeditElements& list, int vertices, const std::string& keyword) {
    if (list.seen) in_.fail("a second " + keyword + " section is not supported");
    list.seen = true;
    const int count = record_count(keyword);
    list.numbers.reserve(in_.records_that_fit(count, vertices + 1) * static_cast<std::size_t>(vertices));
    for (int i = 0; i < count; ++i) {
      in_.require_data_line(keyword, i + 1, count);
      for (int k = 0; k < vertices; ++k) list.numbers.push_back(in_.read_int("vertex number"));
      list.refs.push_back(in_.read_int_in("element reference", std::numeric_limits<int>::min(),
                                          std::numeric_limits<int>::max()));
      in_.expect_line_end("the element reference");
      list.lines.push_back(in_.line_number());
    }
  }

  void skip_records(const std::string& keyword) {
    if (in_.at_line_end() && !in_.next_data_line()) return;  // a keyword without records ends the file
    std::string_view token;
    in_.next_token(token);
    std::int64_t count = -1;
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), count);
    if (ec != std::errc() || ptr != token.data() + token.size() || count < 0) {
      in_.fail("unknown keyword '" + keyword + "' is not followed by a record count");
    }
    for (std::int64_t i = 0; i < count; ++i) {
      in_.require_data_line(keyword, i + 1, count);
    }
  }

  Mesh assemble() {
    const std::string& path = in_.path();
    if (dim_ == 0) throw MeshError(path + ": no Dimension keyword");
    const bool have_tets = !tets_.refs.empty();
    if (have_tets && dim_ != 3) {
      throw MeshError(path + ":" + std::to_string(tets_.lines.front()) + ": Tetrahedra in a 2D file");
    }
    const MeditElements& kept = have_tets ? tets_ : triangles_;
    if (kept.refs.empty()) throw MeshError(path + ": no Tetrahedra or Triangles in the file");

    RawMesh raw;
    raw.dim = dim_;
    raw.coordinates = std::move(coordinates_);
    raw.regions = kept.refs;
    raw.element_lines = kept.lines;
    mesh_detail::set_elements_from_numbers(raw, kept.numbers, have_tets ? 4 : 3, 1, path);
    if (!have_tets && dim_ == 3) mesh_detail::flatten_triangles(raw, path);
    return mesh_detail::finish_mesh(raw, path);
  }

  TextScanner in_;
  int dim_ = 0;
  bool seen_vertices_ = false;
  std::vector<double> coordinates_;
  MeditElements tets_;
  MeditElements triangles_;
};

}  // namespace

Mesh read_medit(const std::string& path) { return MeditReader(path).read(); }

}  // namespace tailor
