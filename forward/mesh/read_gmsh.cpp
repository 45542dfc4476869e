// Gmsh .msh reader, ASCII format 2.x and 4.1.
//
// Only the sections that define the mesh are interpreted: $MeshFormat, $Entities (4.1, for
// the physical tag of each entity), $Nodes and $Elements; every other section is skipped.
// Node tags are resolved only after the whole file is read, so any tag numbering works.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "forward/mesh/mesh_io.hpp"
#include "forward/mesh/text_scanner_detail.hpp"

namespace tailor {
namespace {

using mesh_detail::RawMesh;
using mesh_detail::TextScanner;

constexpr int kTriangleType = 2;
constexpr int kTetrahedronType = 4;

// Higher-order triangles and tetrahedra. Keeping only their corners would silently turn a
// curved mesh into a different straight one, so such files are rejected.
bool is_higher_order_simplex(int type) {
  constexpr int kTypes[] = {9, 11, 20, 21, 22, 23, 24, 25, 29, 30, 31};
  return std::find(std::begin(kTypes), std::end(kTypes), type) != std::end(kTypes);
}

// Elements of one kept type, with node tags still unresolved.
struct GmshElements {
  std::vector<std::int64_t> node_tags;  // nodes_per_element per element
  std::vector<std::int64_t> tags;
  std::vector<int> lines;
  std::vector<int> regions;  // format 2: the physical tag
  std::vector<int> blocks;   // format 4: index into GmshReader::blocks_
};

// Maps node tags to 0-based vertex indices: arithmetic when tags are consecutive (the usual
// case), binary search otherwise.
class NodeTagIndex {
 public:
  void build(const std::vector<std::int64_t>& tags, const std::vector<int>& lines, const std::string& path) {
    first_ = tags.empty() ? 0 : tags.front();
    consecutive_ = true;
    for (std::size_t i = 0; i < tags.size() && consecutive_; ++i) {
      consecutive_ = tags[i] == first_ + static_cast<std::int64_t>(i);
    }
    count_ = tags.size();
    if (consecutive_) return;
    sorted_.resize(tags.size());
    for (std::size_t i = 0; i < tags.size(); ++i) sorted_[i] = {tags[i], static_cast<int>(i)};
    std::sort(sorted_.begin(), sorted_.end());
    for (std::size_t i = 1; i < sorted_.size(); ++i) {
      if (sorted_[i].first == sorted_[i - 1].first) {
        const int a = std::min(sorted_[i].second, sorted_[i - 1].second);
        const int b = std::max(sorted_[i].second, sorted_[i - 1].second);
        throw MeshError(path + ":" + std::to_string(lines[b]) + ": node " + std::to_string(sorted_[i].first) +
                        " is defined again (first on line " + std::to_string(lines[a]) + ")");
      }
    }
  }

  // -1 when no node has this tag.
  int find(std::int64_t tag) const {
    if (consecutive_) {
      const std::int64_t i = tag - first_;
      return i >= 0 && i < static_cast<std::int64_t>(count_) ? static_cast<int>(i) : -1;
    }
    const auto it = std::lower_bound(sorted_.begin(), sorted_.end(), std::make_pair(tag, -1));
    return it != sorted_.end() && it->first == tag ? it->second : -1;
  }

 private:
  bool consecutive_ = true;
  std::int64_t first_ = 0;
  std::size_t count_ = 0;
  std::vector<std::pair<std::int64_t, int>> sorted_;
};

class GmshReader {
 public:
  explicit GmshReader(const std::string& path) : in_(path) {}

  Mesh read() {
    read_format();
    while (in_.next_data_line()) {
      std::string_view keyword;
      in_.next_token(keyword);
      if (keyword.empty() || keyword.front() != '$') {
        in_.fail("expected a section such as $Nodes, found " + mesh_detail::quoted_token(keyword));
      }
      const std::string section(keyword.substr(1));
      if (section == "Nodes") {
        if (seen_nodes_) in_.fail("a second $Nodes section is not supported");
        seen_nodes_ = true;
        version_ == 4 ? read_nodes_v4() : read_nodes_v2();
      } else if (section == "Elements") {
        if (seen_elements_) in_.fail("a second $Elements section is not supported");
        seen_elements_ = true;
        version_ == 4 ? read_elements_v4() : read_elements_v2();
      } else if (section == "Entities" && version_ == 4) {
        read_entities();
      } else {
        skip_section(section);
        continue;
      }
      expect_section_end(section);
    }
    return assemble();
  }

 private:
  void read_format() {
    std::string_view keyword;
    if (!in_.next_data_line() || !in_.next_token(keyword) || keyword != "$MeshFormat") {
      in_.fail("not a Gmsh mesh file: expected $MeshFormat on the first line");
    }
    in_.require_data_line("$MeshFormat");
    const std::string_view version = in_.token("format version");
    const std::int64_t file_type = in_.read_int("file type");
    if (file_type != 0) {
      in_.fail("binary Gmsh files are not supported; save the mesh as ASCII (Gmsh option Mesh.Binary = 0)");
    }
    if (version == "2" || version == "2.0" || version == "2.1" || version == "2.2") {
      version_ = 2;
    } else if (version == "4.1") {
      version_ = 4;
    } else {
      in_.fail("unsupported Gmsh format version " + std::string(version) + " (supported: ASCII 2.2 and 4.1)");
    }
    in_.read_int("data size");
    expect_section_end("MeshFormat");
  }

  void expect_section_end(const std::string& section) {
    const std::string end = "$End" + section;
    in_.require_data_line(end);
    std::string_view token;
    in_.next_token(token);
    if (token != end) {
      in_.fail("expected " + end + ", found " + mesh_detail::quoted_token(token) +
               " (does the section hold more records than its header announces?)");
    }
  }

  void skip_section(const std::string& section) {
    const std::string end = "$End" + section;
    const int start = in_.line_number();
    while (in_.next_line()) {
      std::string_view token;
      if (in_.next_token(token) && token == end) return;
    }
    in_.fail_eof("section $" + section + " started on line " + std::to_string(start) + " (no " + end + ")");
  }

  int read_count(const std::string& what) {
    return in_.read_int_in(what, 0, std::numeric_limits<int>::max() / 8);
  }

  void read_node_coordinates(bool allow_more) {
    for (int k = 0; k < 3; ++k) coordinates_.push_back(in_.read_finite("node coordinate"));
    if (!allow_more) in_.expect_line_end("the node coordinates");
  }

  void read_nodes_v2() {
    in_.require_data_line("$Nodes");
    const int count = read_count("number of nodes");
    in_.expect_line_end("the number of nodes");
    for (int i = 0; i < count; ++i) {
      in_.require_data_line("$Nodes: node", i + 1, count);
      node_tags_.push_back(in_.read_int("node tag"));
      node_lines_.push_back(in_.line_number());
      read_node_coordinates(false);
    }
  }

  void read_nodes_v4() {
    in_.require_data_line("$Nodes");
    const int num_blocks = read_count("number of node blocks");
    const int count = read_count("number of nodes");
    for (int b = 0; b < num_blocks; ++b) {
      in_.require_data_line("$Nodes: block", b + 1, num_blocks);
      in_.read_int("entity dimension");
      in_.read_int("entity tag");
      const bool parametric = in_.read_int_in("parametric flag", 0, 1) == 1;
      const int in_block = read_count("number of nodes in the block");
      // A block lists all its node tags first, then all their coordinates.
      for (int i = 0; i < in_block; ++i) {
        in_.require_data_line("$Nodes: tag of block node", i + 1, in_block);
        node_tags_.push_back(in_.read_int("node tag"));
        node_lines_.push_back(in_.line_number());
        in_.expect_line_end("the node tag");
      }
      for (int i = 0; i < in_block; ++i) {
        in_.require_data_line("$Nodes: coordinates of block node", i + 1, in_block);
        read_node_coordinates(parametric);
      }
    }
    if (node_tags_.size() != static_cast<std::size_t>(count)) {
      in_.fail("the $Nodes header announces " + std::to_string(count) + " nodes, but its blocks hold " +
               std::to_string(node_tags_.size()));
    }
  }

  // Reads the rest of an element line after its tag and type; false for types not kept.
  bool read_element_nodes(int type, std::int64_t tag, int region, int block) {
    if (is_higher_order_simplex(type)) {
      in_.fail("element " + std::to_string(tag) + " has Gmsh type " + std::to_string(type) +
               " (a higher-order simplex), which is not supported; export a first-order mesh");
    }
    if (type != kTetrahedronType && type != kTriangleType) return false;
    GmshElements& list = type == kTetrahedronType ? tets_ : triangles_;
    const int nodes = type == kTetrahedronType ? 4 : 3;
    for (int k = 0; k < nodes; ++k) list.node_tags.push_back(in_.read_int("element node tag"));
    in_.expect_line_end("the element's nodes");
    list.tags.push_back(tag);
    list.lines.push_back(in_.line_number());
    list.regions.push_back(region);
    list.blocks.push_back(block);
    return true;
  }

  void read_elements_v2() {
    in_.require_data_line("$Elements");
    const int count = read_count("number of elements");
    in_.expect_line_end("the number of elements");
    for (int i = 0; i < count; ++i) {
      in_.require_data_line("$Elements: element", i + 1, count);
      const std::int64_t tag = in_.read_int("element tag");
      const int type =
          in_.read_int_in("element type", std::numeric_limits<int>::min(), std::numeric_limits<int>::max());
      const int num_tags = in_.read_int_in("number of element tags", 0, 1000);
      int region = 0;
      for (int t = 0; t < num_tags; ++t) {
        const auto value = in_.read_int_in("element tag value", std::numeric_limits<int>::min(),
                                           std::numeric_limits<int>::max());
        if (t == 0) region = value;  // the physical tag comes first
      }
      read_element_nodes(type, tag, region, -1);
    }
  }

  void read_elements_v4() {
    in_.require_data_line("$Elements");
    const int num_blocks = read_count("number of element blocks");
    const int count = read_count("number of elements");
    int seen = 0;
    for (int b = 0; b < num_blocks; ++b) {
      in_.require_data_line("$Elements: block", b + 1, num_blocks);
      const int entity_dim = in_.read_int_in("entity dimension", 0, 3);
      const int entity_tag =
          in_.read_int_in("entity tag", std::numeric_limits<int>::min(), std::numeric_limits<int>::max());
      const int type =
          in_.read_int_in("element type", std::numeric_limits<int>::min(), std::numeric_limits<int>::max());
      const int in_block = read_count("number of elements in the block");
      blocks_.emplace_back(entity_dim, entity_tag);
      for (int i = 0; i < in_block; ++i) {
        in_.require_data_line("$Elements: block element", i + 1, in_block);
        const std::int64_t tag = in_.read_int("element tag");
        read_element_nodes(type, tag, 0, static_cast<int>(blocks_.size()) - 1);
      }
      seen += in_block;
    }
    if (seen != count) {
      in_.fail("the $Elements header announces " + std::to_string(count) + " elements, but its blocks hold " +
               std::to_string(seen));
    }
  }

  void read_entities() {
    in_.require_data_line("$Entities");
    int counts[4];
    for (int d = 0; d < 4; ++d) counts[d] = read_count("number of entities");
    for (int d = 0; d < 4; ++d) {
      for (int i = 0; i < counts[d]; ++i) {
        in_.require_data_line("$Entities: entity", i + 1, counts[d]);
        const int tag =
            in_.read_int_in("entity tag", std::numeric_limits<int>::min(), std::numeric_limits<int>::max());
        // Points carry a position, other entities a bounding box.
        for (int k = 0; k < (d == 0 ? 3 : 6); ++k) in_.read_double("entity coordinate");
        const int num_physical = read_count("number of physical tags");
        int physical = 0;
        if (num_physical > 0) {
          physical = in_.read_int_in("physical tag", std::numeric_limits<int>::min(),
                                     std::numeric_limits<int>::max());
        }
        physical_of_entity_[{d, tag}] = physical;
      }
    }
  }

  Mesh assemble() {
    const std::string& path = in_.path();
    if (!seen_nodes_) throw MeshError(path + ": no $Nodes section");
    const bool have_tets = !tets_.tags.empty();
    const GmshElements& kept = have_tets ? tets_ : triangles_;
    if (kept.tags.empty()) {
      throw MeshError(path + ": no tetrahedra (Gmsh type 4) or triangles (type 2) in the file");
    }
    NodeTagIndex index;
    index.build(node_tags_, node_lines_, path);

    RawMesh raw;
    raw.dim = 3;
    raw.coordinates = std::move(coordinates_);
    const int nodes = have_tets ? 4 : 3;
    raw.elements.resize(kept.node_tags.size());
    for (std::size_t e = 0; e < kept.tags.size(); ++e) {
      for (int k = 0; k < nodes; ++k) {
        const std::int64_t tag = kept.node_tags[e * nodes + k];
        const int vertex = index.find(tag);
        if (vertex < 0) {
          throw MeshError(path + ":" + std::to_string(kept.lines[e]) + ": element " +
                          std::to_string(kept.tags[e]) + " references node " + std::to_string(tag) +
                          ", but only " + std::to_string(node_tags_.size()) +
                          " nodes are defined and none has that tag");
        }
        raw.elements[e * nodes + k] = vertex;
      }
    }
    raw.element_lines = kept.lines;
    raw.regions.resize(kept.tags.size());
    for (std::size_t e = 0; e < kept.tags.size(); ++e) {
      if (version_ == 2) {
        raw.regions[e] = kept.regions[e];
      } else {
        const auto it = physical_of_entity_.find(blocks_[static_cast<std::size_t>(kept.blocks[e])]);
        raw.regions[e] = it == physical_of_entity_.end() ? 0 : it->second;
      }
    }
    if (!have_tets) mesh_detail::flatten_triangles(raw, path);
    return mesh_detail::finish_mesh(raw, path);
  }

  TextScanner in_;
  int version_ = 0;
  bool seen_nodes_ = false;
  bool seen_elements_ = false;
  std::vector<std::int64_t> node_tags_;
  std::vector<int> node_lines_;
  std::vector<double> coordinates_;  // 3 per node
  GmshElements tets_;
  GmshElements triangles_;
  std::vector<std::pair<int, int>> blocks_;  // (entity dimension, entity tag) per element block
  std::map<std::pair<int, int>, int> physical_of_entity_;
};

}  // namespace

Mesh read_gmsh(const std::string& path) { return GmshReader(path).read(); }

}  // namespace tailor
