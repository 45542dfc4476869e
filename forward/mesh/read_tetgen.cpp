// TetGen .node/.ele reader (and Triangle's, which share the layout in 2D).
//
// Points are numbered from 0 or 1, as chosen by the first point of the .node file; the
// .ele file uses the same numbering. Both files may carry attributes; the first element
// attribute is TetGen's region attribute and becomes the element region.
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "forward/core/format_number.hpp"
#include "forward/mesh/mesh_io.hpp"
#include "forward/mesh/text_scanner_detail.hpp"

namespace tailor {
namespace {

using mesh_detail::RawMesh;
using mesh_detail::TextScanner;

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Reads the .node file into raw.coordinates; returns the numbering base (0 or 1).
int read_node_file(const std::string& path, RawMesh& raw) {
  TextScanner in(path, '#');
  in.require_data_line("the .node header");
  const int count = in.read_int_in("number of points", 0, std::numeric_limits<int>::max() / 8);
  if (count == 0) in.fail("no points (points given in a .poly file are not supported)");
  raw.dim = in.read_int_in("dimension", 2, 3);
  // Attributes and the marker are optional in the header; absent means none.
  const int num_attributes = in.at_line_end() ? 0 : in.read_int_in("number of point attributes", 0, 1000);
  const int num_markers = in.at_line_end() ? 0 : in.read_int_in("number of boundary markers", 0, 1);
  in.expect_line_end("the .node header");

  raw.coordinates.reserve(in.records_that_fit(count, 1 + raw.dim + num_attributes + num_markers) *
                          static_cast<std::size_t>(raw.dim));
  int base = 0;
  for (int i = 0; i < count; ++i) {
    in.require_data_line("point", i + 1, count);
    const std::int64_t number = in.read_int("point number");
    if (i == 0) {
      if (number != 0 && number != 1)
        in.fail("the first point is numbered " + std::to_string(number) + ", expected 0 or 1");
      base = static_cast<int>(number);
    } else if (number != base + i) {
      in.fail("point number " + std::to_string(number) + " where " + std::to_string(base + i) +
              " was expected (points must be numbered consecutively)");
    }
    for (int k = 0; k < raw.dim; ++k) raw.coordinates.push_back(in.read_finite("point coordinate"));
    for (int a = 0; a < num_attributes; ++a) in.read_double("point attribute");
    for (int m = 0; m < num_markers; ++m) in.read_int("boundary marker");
    in.expect_line_end("the point record");
  }
  return base;
}

void read_ele_file(const std::string& path, int base, RawMesh& raw) {
  TextScanner in(path, '#');
  in.require_data_line("the .ele header");
  const int count = in.read_int_in("number of elements", 1, std::numeric_limits<int>::max() / 8);
  const int corners = raw.dim + 1;
  const int nodes = in.read_int_in("nodes per element", 0, std::numeric_limits<int>::max());
  // Quadratic elements list their corners first; the mid-edge points sit exactly on the
  // straight edges in TetGen's output, so dropping them keeps the geometry.
  const int quadratic = raw.dim == 3 ? 10 : 6;
  if (nodes != corners && nodes != quadratic) {
    in.fail(std::to_string(nodes) + " nodes per element; a " + std::to_string(raw.dim) +
            "D mesh (from the .node file) needs " + std::to_string(corners) + " or " +
            std::to_string(quadratic));
  }
  const int num_attributes = in.at_line_end() ? 0 : in.read_int_in("number of element attributes", 0, 1000);
  in.expect_line_end("the .ele header");

  std::vector<std::int64_t> numbers;
  const std::size_t records = in.records_that_fit(count, 1 + nodes + num_attributes);
  numbers.reserve(records * static_cast<std::size_t>(corners));
  raw.regions.reserve(records);
  raw.element_lines.reserve(records);
  for (int i = 0; i < count; ++i) {
    in.require_data_line("element", i + 1, count);
    in.read_int("element number");
    for (int k = 0; k < nodes; ++k) {
      const std::int64_t number = in.read_int("element point number");
      if (k < corners) numbers.push_back(number);
    }
    int region = 0;
    for (int a = 0; a < num_attributes; ++a) {
      const double attribute = in.read_finite("element attribute");
      if (a > 0) continue;
      // TetGen writes region attributes as numbers; a region must be an integer label.
      if (attribute != std::round(attribute) || std::abs(attribute) > std::numeric_limits<int>::max()) {
        in.fail("region attribute " + format_number(attribute) + " is not an integer");
      }
      region = static_cast<int>(attribute);
    }
    in.expect_line_end("the element record");
    raw.regions.push_back(region);
    raw.element_lines.push_back(in.line_number());
  }
  mesh_detail::set_elements_from_numbers(raw, numbers, corners, base, path);
}

}  // namespace

Mesh read_tetgen(const std::string& path) {
  std::string base_name = path;
  if (ends_with(path, ".node")) base_name.resize(path.size() - 5);
  if (ends_with(path, ".ele")) base_name.resize(path.size() - 4);
  RawMesh raw;
  const int base = read_node_file(base_name + ".node", raw);
  const std::string ele_path = base_name + ".ele";
  read_ele_file(ele_path, base, raw);
  return mesh_detail::finish_mesh(raw, ele_path);
}

}  // namespace tailor
