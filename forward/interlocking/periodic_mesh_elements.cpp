// Triangle-mesh elements of periodic cells (see periodic_mesh_elements.hpp).
#include "forward/interlocking/periodic_mesh_elements.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "forward/tori/torus.hpp"

namespace tailor::interlocking {

double torus_chordal_bound(const tori::TorusShape& shape, int major, int minor) {
  const double r = std::max(shape.minor_radius, tori::axial_radius(shape));
  return r * (1.0 - std::cos(M_PI / minor)) + (shape.major_radius + r) * (1.0 - std::cos(M_PI / major));
}

std::shared_ptr<const ElementMesh> torus_mesh(const tori::TorusShape& shape, int major, int minor) {
  tori::validate_shape(shape, "meshed torus");
  auto mesh = std::make_shared<ElementMesh>();
  tori::torus_surface(shape, major, minor, false, mesh->vertices, mesh->faces);
  mesh->source = "torus " + std::to_string(major) + " x " + std::to_string(minor);
  mesh->chordal_error = torus_chordal_bound(shape, major, minor);
  return mesh;
}

namespace {

[[noreturn]] void fail_at(const std::string& path, int line, const std::string& what) {
  throw std::runtime_error(path + ":" + std::to_string(line) + ": " + what);
}

// A 1-based OBJ index ("7", "7/2", "7//3", negative: relative to the end).
int obj_index(const std::string& token, int count, const std::string& path, int line) {
  const std::string head = token.substr(0, token.find('/'));
  std::size_t used = 0;
  int k = 0;
  try {
    k = std::stoi(head, &used);
  } catch (const std::exception&) {
    fail_at(path, line, "bad face index '" + token + "'");
  }
  if (used != head.size() || k == 0) fail_at(path, line, "bad face index '" + token + "'");
  const int index = k > 0 ? k - 1 : count + k;
  if (index < 0 || index >= count) fail_at(path, line, "face index " + head + " outside the vertices read so far");
  return index;
}

void read_obj(std::istream& in, const std::string& path, std::vector<Eigen::Vector3d>& v,
              std::vector<Eigen::Vector3i>& f) {
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    std::istringstream s(text);
    std::string key;
    if (!(s >> key) || key[0] == '#') continue;
    if (key == "v") {
      Eigen::Vector3d p;
      if (!(s >> p.x() >> p.y() >> p.z())) fail_at(path, line, "a vertex needs three coordinates");
      v.push_back(p);
    } else if (key == "f") {
      std::vector<std::string> tokens;
      for (std::string t; s >> t;) tokens.push_back(t);
      if (tokens.size() != 3)
        fail_at(path, line, "faces must be triangles (got " + std::to_string(tokens.size()) + " vertices)");
      Eigen::Vector3i face;
      for (int k = 0; k < 3; ++k)
        face[k] = obj_index(tokens[static_cast<std::size_t>(k)], static_cast<int>(v.size()), path, line);
      f.push_back(face);
    }  // normals, texture coordinates, groups, materials: not geometry
  }
}

void read_off(std::istream& in, const std::string& path, std::vector<Eigen::Vector3d>& v,
              std::vector<Eigen::Vector3i>& f) {
  // Tokens with their line numbers, comments dropped.
  std::vector<std::pair<std::string, int>> tokens;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    std::istringstream s(text.substr(0, text.find('#')));
    for (std::string t; s >> t;) tokens.emplace_back(t, line);
  }
  std::size_t at = 0;
  const auto next = [&](const char* what) -> const std::pair<std::string, int>& {
    if (at >= tokens.size()) fail_at(path, tokens.empty() ? 1 : tokens.back().second, std::string("missing ") + what);
    return tokens[at++];
  };
  const auto number = [&](const char* what) {
    const auto& [t, line] = next(what);
    try {
      std::size_t used = 0;
      const double x = std::stod(t, &used);
      if (used == t.size()) return x;
    } catch (const std::exception&) {
    }
    fail_at(path, line, std::string("bad ") + what + " '" + t + "'");
  };
  const auto count = [&](const char* what) {
    const double x = number(what);
    if (!(x >= 0.0) || x != std::floor(x)) fail_at(path, tokens[at - 1].second, std::string("bad ") + what);
    return static_cast<int>(x);
  };
  if (next("the OFF header").first != "OFF") fail_at(path, tokens[0].second, "expected the header 'OFF'");
  const int nv = count("vertex count"), nf = count("face count");
  count("edge count");
  for (int i = 0; i < nv; ++i) {
    const double x = number("vertex coordinate"), y = number("vertex coordinate"), z = number("vertex coordinate");
    v.emplace_back(x, y, z);
  }
  for (int i = 0; i < nf; ++i) {
    const int n = count("face size");
    if (n != 3) fail_at(path, tokens[at - 1].second, "faces must be triangles (got " + std::to_string(n) + ")");
    Eigen::Vector3i face;
    for (int k = 0; k < 3; ++k) {
      face[k] = count("face index");
      if (face[k] >= nv) fail_at(path, tokens[at - 1].second, "face index outside the vertices");
    }
    f.push_back(face);
    // Colour values may follow a face on its line: skip them.
    const int line = tokens[at - 1].second;
    while (at < tokens.size() && tokens[at].second == line) ++at;
  }
}

}  // namespace

std::shared_ptr<const ElementMesh> read_element_mesh(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".obj" && ext != ".off") throw std::runtime_error(path + ": expected an .obj or .off file");
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open file for reading");
  std::vector<Eigen::Vector3d> v;
  std::vector<Eigen::Vector3i> f;
  if (ext == ".obj")
    read_obj(in, path, v, f);
  else
    read_off(in, path, v, f);
  auto mesh = std::make_shared<ElementMesh>();
  mesh->vertices.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i) mesh->vertices.row(static_cast<Eigen::Index>(i)) = v[i].transpose();
  mesh->faces.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t i = 0; i < f.size(); ++i) mesh->faces.row(static_cast<Eigen::Index>(i)) = f[i].transpose();
  mesh->source = std::filesystem::path(path).filename().string();
  try {
    validate_element_mesh(*mesh, path);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(e.what());
  }
  return mesh;
}

void validate_element_mesh(const ElementMesh& mesh, const std::string& where) {
  if (mesh.vertices.rows() == 0 || mesh.faces.rows() == 0)
    throw std::invalid_argument(where + ": the mesh has no vertices or no faces");
  if (!mesh.vertices.allFinite()) throw std::invalid_argument(where + ": the mesh has a non-finite vertex");
  if (mesh.faces.minCoeff() < 0 || mesh.faces.maxCoeff() >= mesh.vertices.rows())
    throw std::invalid_argument(where + ": a face index lies outside the mesh's vertices");
  const double scale = mesh_bounding_radius(mesh);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0)), b = mesh.vertices.row(mesh.faces(f, 1)),
                          c = mesh.vertices.row(mesh.faces(f, 2));
    if (!((b - a).cross(c - a).norm() > 1e-14 * scale * scale))
      throw std::invalid_argument(where + ": face " + std::to_string(f) + " is degenerate (zero area)");
  }
}

double mesh_bounding_radius(const ElementMesh& mesh) { return mesh.vertices.rowwise().norm().maxCoeff(); }

RigidCellSpec with_torus_meshes(RigidCellSpec spec, int major, int minor) {
  for (CellElement& e : spec.elements) e.mesh = torus_mesh(e.shape, major, minor);
  return spec;
}

bool is_mesh_cell(const RigidCellSpec& spec) {
  return !spec.elements.empty() && spec.elements.front().mesh != nullptr;
}

}  // namespace tailor::interlocking
