#include "forward/meshless/point_cloud_io.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <utility>

namespace tailor {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) { throw PointInputError(path + ": " + what); }

std::string lower_extension(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  std::string e = dot == std::string::npos ? "" : path.substr(dot + 1);
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

std::ifstream open(const std::string& path, bool binary = false) {
  std::ifstream in(path, binary ? std::ios::binary : std::ios::in);
  if (!in) fail(path, "cannot be opened");
  return in;
}

// The numbers of a line up to a '#'; false when a token is not a number.
bool split_numbers(const std::string& line, std::vector<double>& numbers) {
  numbers.clear();
  std::istringstream s(line.substr(0, line.find('#')));
  std::string token;
  while (s >> token) {
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0') return false;
    numbers.push_back(v);
  }
  return true;
}

OrientedPoints from_rows(const std::string& path, const std::vector<std::array<double, 6>>& rows, std::vector<int> lines) {
  OrientedPoints p;
  p.source = path;
  p.positions.resize(static_cast<Eigen::Index>(rows.size()), 3);
  p.normals.resize(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      p.positions(static_cast<Eigen::Index>(i), k) = rows[i][static_cast<std::size_t>(k)];
      p.normals(static_cast<Eigen::Index>(i), k) = rows[i][static_cast<std::size_t>(k + 3)];
    }
  p.lines = std::move(lines);
  validate_oriented_points(p);
  return p;
}

// ---- PLY

struct PlyProperty {
  std::string name, type, count_type;  // count_type non-empty: a list
};
struct PlyElement {
  std::string name;
  long count = 0;
  std::vector<PlyProperty> properties;
};

int ply_size(const std::string& path, const std::string& type) {
  static const std::map<std::string, int> sizes = {
      {"char", 1},  {"uchar", 1},  {"int8", 1},   {"uint8", 1},  {"short", 2},   {"ushort", 2},
      {"int16", 2}, {"uint16", 2}, {"int", 4},    {"uint", 4},   {"int32", 4},   {"uint32", 4},
      {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
  const auto it = sizes.find(type);
  if (it == sizes.end()) fail(path, "unknown PLY property type '" + type + "'");
  return it->second;
}

double ply_binary_value(const std::string& type, const char* b) {
  // Little-endian hosts only (x86-64, arm64): the bytes are copied as they are.
  if (type == "char" || type == "int8") return static_cast<double>(static_cast<std::int8_t>(b[0]));
  if (type == "uchar" || type == "uint8") return static_cast<double>(static_cast<std::uint8_t>(b[0]));
  if (type == "short" || type == "int16") { std::int16_t v; std::memcpy(&v, b, 2); return v; }
  if (type == "ushort" || type == "uint16") { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
  if (type == "int" || type == "int32") { std::int32_t v; std::memcpy(&v, b, 4); return v; }
  if (type == "uint" || type == "uint32") { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
  if (type == "float" || type == "float32") { float v; std::memcpy(&v, b, 4); return static_cast<double>(v); }
  double v;
  std::memcpy(&v, b, 8);
  return v;
}

struct PlyData {
  std::vector<std::array<double, 6>> vertices;  // x y z nx ny nz
  bool has_normals = false;
  std::vector<std::vector<int>> faces;
  std::vector<int> vertex_lines, face_lines;
};

PlyData read_ply(const std::string& path) {
  std::ifstream in = open(path, true);
  std::string line;
  int line_number = 0;
  auto next_line = [&]() {
    if (!std::getline(in, line)) fail(path, "ends inside the PLY header");
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
  };
  next_line();
  if (line != "ply") fail(path, "line 1: not a PLY file (no 'ply' magic)");
  bool ascii = false;
  std::vector<PlyElement> elements;
  for (;;) {
    next_line();
    std::istringstream s(line);
    std::string word;
    s >> word;
    if (word == "end_header") break;
    if (word == "comment" || word == "obj_info" || word.empty()) continue;
    if (word == "format") {
      std::string format;
      s >> format;
      if (format == "ascii") ascii = true;
      else if (format == "binary_big_endian")
        fail(path, "line " + std::to_string(line_number) + ": binary_big_endian PLY is not supported (convert it to little-endian or ASCII)");
      else if (format != "binary_little_endian")
        fail(path, "line " + std::to_string(line_number) + ": unknown PLY format '" + format + "'");
    } else if (word == "element") {
      PlyElement e;
      if (!(s >> e.name >> e.count) || e.count < 0) fail(path, "line " + std::to_string(line_number) + ": bad element line");
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) fail(path, "line " + std::to_string(line_number) + ": property before any element");
      PlyProperty p;
      std::string type;
      s >> type;
      if (type == "list") {
        s >> p.count_type >> p.type >> p.name;
        ply_size(path, p.count_type);
      } else {
        p.type = type;
        s >> p.name;
      }
      ply_size(path, p.type);
      elements.back().properties.push_back(p);
    } else {
      fail(path, "line " + std::to_string(line_number) + ": unexpected PLY header line '" + line + "'");
    }
  }
  PlyData data;
  for (const PlyElement& e : elements) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    std::array<int, 6> slot{-1, -1, -1, -1, -1, -1};
    int list_index = -1;
    for (std::size_t k = 0; k < e.properties.size(); ++k) {
      static const std::array<const char*, 6> names = {"x", "y", "z", "nx", "ny", "nz"};
      for (std::size_t c = 0; c < 6; ++c)
        if (is_vertex && e.properties[k].name == names[c] && e.properties[k].count_type.empty()) slot[c] = static_cast<int>(k);
      if (is_face && !e.properties[k].count_type.empty() &&
          (e.properties[k].name == "vertex_indices" || e.properties[k].name == "vertex_index"))
        list_index = static_cast<int>(k);
    }
    if (is_vertex) {
      if (slot[0] < 0 || slot[1] < 0 || slot[2] < 0) fail(path, "the PLY vertex element has no x, y, z properties");
      data.has_normals = slot[3] >= 0 && slot[4] >= 0 && slot[5] >= 0;
    }
    if (is_face && list_index < 0) fail(path, "the PLY face element has no vertex_indices list");
    for (long i = 0; i < e.count; ++i) {
      std::vector<double> values(e.properties.size(), 0.0);
      std::vector<int> list;
      if (ascii) {
        if (!std::getline(in, line)) fail(path, "ends in element '" + e.name + "' " + std::to_string(i));
        ++line_number;
        std::vector<double> numbers;
        if (!split_numbers(line, numbers)) fail(path, "line " + std::to_string(line_number) + ": not a number");
        std::size_t at = 0;
        for (std::size_t k = 0; k < e.properties.size(); ++k) {
          if (at >= numbers.size()) fail(path, "line " + std::to_string(line_number) + ": too few values for element '" + e.name + "'");
          if (e.properties[k].count_type.empty()) {
            values[k] = numbers[at++];
          } else {
            const long count = static_cast<long>(numbers[at++]);
            if (count < 0 || at + static_cast<std::size_t>(count) > numbers.size())
              fail(path, "line " + std::to_string(line_number) + ": bad list length");
            for (long j = 0; j < count; ++j) list.push_back(static_cast<int>(numbers[at++]));
            if (static_cast<int>(k) != list_index) list.clear();
          }
        }
      } else {
        char buffer[8];
        for (std::size_t k = 0; k < e.properties.size(); ++k) {
          const PlyProperty& p = e.properties[k];
          if (p.count_type.empty()) {
            if (!in.read(buffer, ply_size(path, p.type))) fail(path, "ends in " + e.name + " " + std::to_string(i));
            values[k] = ply_binary_value(p.type, buffer);
          } else {
            if (!in.read(buffer, ply_size(path, p.count_type))) fail(path, "ends in " + e.name + " " + std::to_string(i));
            const long count = static_cast<long>(ply_binary_value(p.count_type, buffer));
            if (count < 0 || count > 1000000) fail(path, e.name + " " + std::to_string(i) + ": bad list length");
            std::vector<int> entries;
            for (long j = 0; j < count; ++j) {
              if (!in.read(buffer, ply_size(path, p.type))) fail(path, "ends in " + e.name + " " + std::to_string(i));
              entries.push_back(static_cast<int>(ply_binary_value(p.type, buffer)));
            }
            if (static_cast<int>(k) == list_index) list = std::move(entries);
          }
        }
      }
      if (is_vertex) {
        std::array<double, 6> row{0, 0, 0, 0, 0, 0};
        for (std::size_t c = 0; c < 6; ++c)
          if (slot[c] >= 0) row[c] = values[static_cast<std::size_t>(slot[c])];
        data.vertices.push_back(row);
        data.vertex_lines.push_back(ascii ? line_number : 0);
      } else if (is_face) {
        data.faces.push_back(list);
        data.face_lines.push_back(ascii ? line_number : 0);
      }
    }
  }
  return data;
}

// Fans polygons into triangles; checks the indices.
SurfaceMesh make_mesh(const std::string& path, std::vector<Eigen::Vector3d> vertices, const std::vector<std::vector<int>>& faces,
                      const std::vector<int>& face_lines) {
  SurfaceMesh m;
  m.source = path;
  m.vertices.resize(static_cast<Eigen::Index>(vertices.size()), 3);
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (!vertices[i].allFinite()) fail(path, "vertex " + std::to_string(i) + " is not finite");
    m.vertices.row(static_cast<Eigen::Index>(i)) = vertices[i].transpose();
  }
  std::vector<std::array<int, 3>> triangles;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const std::string where = face_lines[f] > 0 ? "line " + std::to_string(face_lines[f]) : "face " + std::to_string(f);
    if (faces[f].size() < 3) fail(path, where + ": a face needs at least 3 vertices");
    for (int v : faces[f])
      if (v < 0 || v >= static_cast<int>(vertices.size()))
        fail(path, where + ": vertex index " + std::to_string(v) + " out of range (" + std::to_string(vertices.size()) + " vertices)");
    for (std::size_t k = 1; k + 1 < faces[f].size(); ++k) {
      triangles.push_back({faces[f][0], faces[f][k], faces[f][k + 1]});
      m.face_lines.push_back(face_lines[f]);
    }
  }
  if (triangles.empty()) fail(path, "has no faces");
  m.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) m.triangles(static_cast<Eigen::Index>(t), k) = triangles[t][static_cast<std::size_t>(k)];
  return m;
}

}  // namespace

std::string OrientedPoints::describe(int i) const {
  const std::size_t k = static_cast<std::size_t>(i);
  return "point " + std::to_string(i) + (k < lines.size() && lines[k] > 0 ? " (line " + std::to_string(lines[k]) + ")" : "");
}

void validate_oriented_points(OrientedPoints& points) {
  if (points.size() == 0) fail(points.source, "has no points");
  for (int i = 0; i < points.size(); ++i) {
    if (!points.positions.row(i).allFinite()) fail(points.source, points.describe(i) + ": the position is not finite");
    if (!points.normals.row(i).allFinite()) fail(points.source, points.describe(i) + ": the normal is not finite");
    const double length = points.normals.row(i).norm();
    if (!(length > 1e-12)) fail(points.source, points.describe(i) + ": the normal is zero");
    points.normals.row(i) /= length;
  }
}

OrientedPoints read_xyz_points(const std::string& path) {
  std::ifstream in = open(path);
  std::vector<std::array<double, 6>> rows;
  std::vector<int> lines;
  std::string line;
  std::vector<double> numbers;
  int line_number = 0;
  bool first = true;
  while (std::getline(in, line)) {
    ++line_number;
    if (!split_numbers(line, numbers)) fail(path, "line " + std::to_string(line_number) + ": not a number");
    if (numbers.empty()) continue;
    if (first && numbers.size() == 1) {  // a .pts point count
      first = false;
      continue;
    }
    first = false;
    if (numbers.size() < 6)
      fail(path, "line " + std::to_string(line_number) + ": point " + std::to_string(rows.size()) + " has " +
                     std::to_string(numbers.size()) + " values; a point needs x y z nx ny nz (no normals)");
    rows.push_back({numbers[0], numbers[1], numbers[2], numbers[3], numbers[4], numbers[5]});
    lines.push_back(line_number);
  }
  return from_rows(path, rows, std::move(lines));
}

OrientedPoints read_ply_points(const std::string& path) {
  PlyData data = read_ply(path);
  if (!data.faces.empty()) return sample_surface(read_ply_mesh(path), {});
  if (!data.has_normals) fail(path, "the PLY vertices have no normals (nx, ny, nz) and the file has no faces");
  return from_rows(path, data.vertices, data.vertex_lines);
}

SurfaceMesh read_ply_mesh(const std::string& path) {
  PlyData data = read_ply(path);
  std::vector<Eigen::Vector3d> vertices;
  for (const auto& v : data.vertices) vertices.emplace_back(v[0], v[1], v[2]);
  return make_mesh(path, std::move(vertices), data.faces, data.face_lines);
}

SurfaceMesh read_obj_mesh(const std::string& path) {
  std::ifstream in = open(path);
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::vector<int>> faces;
  std::vector<int> face_lines;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    std::istringstream s(line.substr(0, line.find('#')));
    std::string word;
    if (!(s >> word)) continue;
    const std::string where = "line " + std::to_string(line_number);
    if (word == "v") {
      Eigen::Vector3d v;
      if (!(s >> v[0] >> v[1] >> v[2])) fail(path, where + ": a vertex needs x y z");
      if (!v.allFinite()) fail(path, where + ": the vertex is not finite");
      vertices.push_back(v);
    } else if (word == "f") {
      std::vector<int> face;
      std::string token;
      while (s >> token) {
        char* end = nullptr;
        const long index = std::strtol(token.c_str(), &end, 10);
        if (end == token.c_str()) fail(path, where + ": bad face index '" + token + "'");
        // Negative indices count back from the last vertex read (OBJ's relative indices).
        face.push_back(index < 0 ? static_cast<int>(vertices.size()) + static_cast<int>(index) : static_cast<int>(index) - 1);
      }
      faces.push_back(face);
      face_lines.push_back(line_number);
    }
  }
  return make_mesh(path, std::move(vertices), faces, face_lines);
}

SurfaceMesh read_off_mesh(const std::string& path) {
  std::ifstream in = open(path);
  std::string line;
  int line_number = 0;
  std::vector<double> numbers;
  // The data lines, comments and blank lines skipped, with their line numbers.
  auto next = [&](const char* what) {
    while (std::getline(in, line)) {
      ++line_number;
      const std::size_t start = line.find_first_not_of(" \t\r");
      if (start == std::string::npos || line[start] == '#') continue;
      return;
    }
    fail(path, std::string("ends before ") + what);
  };
  next("the OFF header");
  std::string head = line.substr(line.find_first_not_of(" \t"));
  if (head.rfind("OFF", 0) != 0) fail(path, "line " + std::to_string(line_number) + ": not an OFF file (no 'OFF' header)");
  head = head.substr(3);
  if (!split_numbers(head, numbers) || numbers.empty()) {
    next("the counts");
    if (!split_numbers(line, numbers)) fail(path, "line " + std::to_string(line_number) + ": bad counts");
  }
  if (numbers.size() < 2 || numbers[0] < 0 || numbers[1] < 0) fail(path, "line " + std::to_string(line_number) + ": bad counts");
  const long nv = static_cast<long>(numbers[0]), nf = static_cast<long>(numbers[1]);
  std::vector<Eigen::Vector3d> vertices;
  for (long i = 0; i < nv; ++i) {
    next("all vertices were read");
    if (!split_numbers(line, numbers) || numbers.size() < 3) fail(path, "line " + std::to_string(line_number) + ": a vertex needs x y z");
    vertices.emplace_back(numbers[0], numbers[1], numbers[2]);
  }
  std::vector<std::vector<int>> faces;
  std::vector<int> face_lines;
  for (long f = 0; f < nf; ++f) {
    next("all faces were read");
    if (!split_numbers(line, numbers) || numbers.empty() || numbers.size() < 1 + static_cast<std::size_t>(numbers[0]))
      fail(path, "line " + std::to_string(line_number) + ": bad face");
    std::vector<int> face;
    for (int k = 0; k < static_cast<int>(numbers[0]); ++k) face.push_back(static_cast<int>(numbers[static_cast<std::size_t>(k + 1)]));
    faces.push_back(face);
    face_lines.push_back(line_number);
  }
  return make_mesh(path, std::move(vertices), faces, face_lines);
}

SurfaceMesh read_stl_mesh(const std::string& path) {
  std::ifstream in = open(path, true);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<Eigen::Vector3d> corners;
  std::vector<int> lines;
  bool binary = true;
  if (bytes.size() >= 84) {
    std::uint32_t count;
    std::memcpy(&count, bytes.data() + 80, 4);
    binary = bytes.size() == 84 + 50 * static_cast<std::size_t>(count);
    if (binary)
      for (std::uint32_t t = 0; t < count; ++t)
        for (int c = 0; c < 3; ++c) {
          float v[3];
          std::memcpy(v, bytes.data() + 84 + 50 * static_cast<std::size_t>(t) + 12 + 12 * static_cast<std::size_t>(c), 12);
          corners.emplace_back(v[0], v[1], v[2]);
        }
  } else {
    binary = false;
  }
  if (!binary) {
    if (bytes.rfind("solid", 0) != 0) fail(path, "neither an ASCII STL ('solid' header) nor a binary STL of matching size");
    std::istringstream s(bytes);
    std::string line;
    int line_number = 0;
    while (std::getline(s, line)) {
      ++line_number;
      std::istringstream ls(line);
      std::string word;
      ls >> word;
      if (word != "vertex") continue;
      Eigen::Vector3d v;
      if (!(ls >> v[0] >> v[1] >> v[2])) fail(path, "line " + std::to_string(line_number) + ": a vertex needs x y z");
      corners.push_back(v);
      lines.push_back(line_number);
    }
    if (corners.size() % 3 != 0) fail(path, "the number of facet vertices is not a multiple of 3");
  }
  // STL repeats the corners per facet: weld identical positions into shared vertices.
  std::map<std::array<double, 3>, int> index;
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::vector<int>> faces(corners.size() / 3);
  std::vector<int> face_lines(corners.size() / 3, 0);
  for (std::size_t c = 0; c < corners.size(); ++c) {
    const std::array<double, 3> key{corners[c][0], corners[c][1], corners[c][2]};
    auto [it, added] = index.emplace(key, static_cast<int>(vertices.size()));
    if (added) vertices.push_back(corners[c]);
    faces[c / 3].push_back(it->second);
    if (!binary && c % 3 == 0) face_lines[c / 3] = lines[c];
  }
  return make_mesh(path, std::move(vertices), faces, face_lines);
}

double check_closed_surface(const SurfaceMesh& mesh) {
  // Each directed edge must occur once and its reverse once.
  std::map<std::pair<int, int>, int> directed;  // edge -> triangle
  const auto where = [&](int t) {
    const std::size_t k = static_cast<std::size_t>(t);
    return k < mesh.face_lines.size() && mesh.face_lines[k] > 0 ? "line " + std::to_string(mesh.face_lines[k])
                                                              : "triangle " + std::to_string(t);
  };
  for (int t = 0; t < mesh.triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles(t, k), b = mesh.triangles(t, (k + 1) % 3);
      if (a == b) fail(mesh.source, where(t) + ": a degenerate face (repeated vertex " + std::to_string(a) + ")");
      const auto [it, added] = directed.emplace(std::make_pair(a, b), t);
      if (!added)
        fail(mesh.source, where(t) + ": the edge " + std::to_string(a) + "-" + std::to_string(b) + " is traversed in the same direction by " +
                              where(it->second) + " (faces inconsistently oriented, or a non-manifold edge)");
    }
  for (const auto& [edge, t] : directed)
    if (!directed.count({edge.second, edge.first}))
      fail(mesh.source, where(t) + ": the edge " + std::to_string(edge.first) + "-" + std::to_string(edge.second) +
                            " belongs to no other face: the surface is open");
  double volume = 0.0;
  for (int t = 0; t < mesh.triangles.rows(); ++t) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(t, 0)), b = mesh.vertices.row(mesh.triangles(t, 1)),
                          c = mesh.vertices.row(mesh.triangles(t, 2));
    volume += a.dot(b.cross(c)) / 6.0;
  }
  return volume;
}

OrientedPoints sample_surface(const SurfaceMesh& mesh, const SurfaceSamplingOptions& options) {
  const double volume = check_closed_surface(mesh);
  if (!(std::abs(volume) > 0.0)) fail(mesh.source, "the surface encloses no volume");
  const double sign = volume > 0.0 ? 1.0 : -1.0;  // faces wound inwards: turn the normals outwards
  const Eigen::Vector3d lo = mesh.vertices.colwise().minCoeff(), hi = mesh.vertices.colwise().maxCoeff();
  const double spacing = options.spacing > 0.0 ? options.spacing : (hi - lo).norm() / 50.0;
  std::mt19937 random(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<std::array<double, 6>> rows;
  for (int t = 0; t < mesh.triangles.rows(); ++t) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(t, 0)), b = mesh.vertices.row(mesh.triangles(t, 1)),
                          c = mesh.vertices.row(mesh.triangles(t, 2));
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    const double area = 0.5 * cross.norm();
    if (!(area > 0.0)) continue;  // a zero-area sliver carries no samples
    const Eigen::Vector3d n = sign * cross.normalized();
    // A hexagonal packing of spacing s covers sqrt(3)/2 s^2 per point.
    const int count = std::max(1, static_cast<int>(std::lround(area / (spacing * spacing) * 2.0 / std::sqrt(3.0))));
    // Stratified: count strata of equal area along the sqrt-parametrized barycentric square.
    const int side = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(count)))));
    for (int i = 0; i < count; ++i) {
      const double u = (i % side + unit(random)) / side, v = (i / side % side + unit(random)) / side;
      const double su = std::sqrt(u);
      const Eigen::Vector3d X = (1.0 - su) * a + su * (1.0 - v) * b + su * v * c;
      rows.push_back({X[0], X[1], X[2], n[0], n[1], n[2]});
    }
  }
  OrientedPoints p = from_rows(mesh.source, rows, {});
  return p;
}

OrientedPoints read_oriented_points(const std::string& path, const SurfaceSamplingOptions& sampling) {
  const std::string e = lower_extension(path);
  if (e == "xyz" || e == "pts") return read_xyz_points(path);
  if (e == "ply") {
    const PlyData data = read_ply(path);
    if (!data.faces.empty()) return sample_surface(read_ply_mesh(path), sampling);
    return read_ply_points(path);
  }
  if (e == "obj") return sample_surface(read_obj_mesh(path), sampling);
  if (e == "off") return sample_surface(read_off_mesh(path), sampling);
  if (e == "stl") return sample_surface(read_stl_mesh(path), sampling);
  fail(path, "unknown point or surface format '." + e + "' (expected .xyz, .pts, .ply, .obj, .off or .stl)");
}

}  // namespace tailor
