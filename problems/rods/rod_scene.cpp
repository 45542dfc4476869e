#include "problems/rods/rod_scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <stdexcept>

#include "forward/core/elimination.hpp"
#include "forward/rods/bending_term.hpp"
#include "forward/rods/stretching_term.hpp"
#include "forward/rods/twisting_term.hpp"
#include "forward/solve/newton.hpp"
#include "problems/rods/rod_vtu.hpp"
#include "problems/scene.hpp"

namespace tailor {

namespace {

using nlohmann::json;

[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw SceneError("rods scene: " + where + ": " + what);
}

Eigen::Vector3d vec3(const json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 3) fail(where, "expected an array of 3 numbers");
  Eigen::Vector3d v;
  for (int k = 0; k < 3; ++k) {
    if (!j[static_cast<std::size_t>(k)].is_number()) fail(where, "expected numbers");
    v[k] = j[static_cast<std::size_t>(k)].get<double>();
  }
  return v;
}

double number(const json& j, const std::string& key, const std::string& where,
              std::optional<double> fallback = {}) {
  if (!j.contains(key)) {
    if (fallback) return *fallback;
    fail(where, "missing '" + key + "'");
  }
  if (!j[key].is_number()) fail(where + "." + key, "expected a number");
  return j[key].get<double>();
}

// An integer in [lo, hi]; anything else is refused (casting it to int would be undefined).
int integer(const json& j, const std::string& key, const std::string& where, std::optional<int> fallback,
            int lo, int hi) {
  if (!j.contains(key) && fallback) return *fallback;
  const double v = number(j, key, where);
  if (!(v >= lo && v <= hi) || v != std::floor(v))
    fail(where + "." + key,
         "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return static_cast<int>(v);
}

// The member `key` of `j` when it is an object, an empty object when absent.
json object_member(const json& j, const std::string& key, const std::string& where) {
  if (!j.contains(key)) return json::object();
  if (!j[key].is_object()) fail(where + "." + key, "expected an object");
  return j[key];
}

// More vertices than any rod needs; the points are allocated while parsing.
constexpr int kMaxRodVertices = 10'000'000;

Eigen::MatrixX3d points_of(const json& r, const std::string& where) {
  if (r.contains("points")) {
    const json& pts = r["points"];
    if (!pts.is_array() || pts.size() < 3) fail(where + ".points", "expected at least 3 points");
    Eigen::MatrixX3d x(static_cast<Eigen::Index>(pts.size()), 3);
    for (std::size_t i = 0; i < pts.size(); ++i)
      x.row(static_cast<Eigen::Index>(i)) =
          vec3(pts[i], where + ".points[" + std::to_string(i) + "]").transpose();
    return x;
  }
  if (r.contains("line")) {
    const json& l = r["line"];
    if (!l.is_object()) fail(where + ".line", "expected an object with from, to and vertices");
    const Eigen::Vector3d a = vec3(l.value("from", json()), where + ".line.from");
    const Eigen::Vector3d b = vec3(l.value("to", json()), where + ".line.to");
    const int n = integer(l, "vertices", where + ".line", {}, 3, kMaxRodVertices);
    Eigen::MatrixX3d x(n, 3);
    for (int i = 0; i < n; ++i) x.row(i) = (a + (b - a) * (i / (n - 1.0))).transpose();
    return x;
  }
  if (r.contains("circle")) {
    const json& c = r["circle"];
    const std::string w = where + ".circle";
    if (!c.is_object()) fail(w, "expected an object with radius and vertices");
    const Eigen::Vector3d center = c.contains("center") ? vec3(c["center"], w + ".center") : Eigen::Vector3d::Zero();
    const Eigen::Vector3d normal = c.contains("normal") ? vec3(c["normal"], w + ".normal") : Eigen::Vector3d::UnitZ();
    if (!(normal.norm() > 0.0)) fail(w + ".normal", "must be non-zero");
    const double R = number(c, "radius", w);
    if (!(R > 0.0) || !std::isfinite(R)) fail(w + ".radius", "must be positive");
    const double start = number(c, "start_angle", w, 0.0);
    const int n = integer(c, "vertices", w, {}, 3, kMaxRodVertices);
    const Eigen::Vector3d z = normal.normalized();
    Eigen::Index k = 0;
    z.cwiseAbs().minCoeff(&k);
    const Eigen::Vector3d u = (Eigen::Vector3d::Unit(k) - z[k] * z).normalized(), v = z.cross(u);
    Eigen::MatrixX3d x(n, 3);
    for (int i = 0; i < n; ++i) {
      const double phi = start + 2.0 * M_PI * i / n;
      x.row(i) = (center + R * (std::cos(phi) * u + std::sin(phi) * v)).transpose();
    }
    return x;
  }
  fail(where, "needs 'points', 'line' or 'circle'");
}

bool boolean(const json& j, const std::string& key, const std::string& where, bool fallback) {
  if (!j.contains(key)) return fallback;
  if (!j[key].is_boolean()) fail(where + "." + key, "expected true or false");
  return j[key].get<bool>();
}

}  // namespace

void RodLoadTerm::evaluate(const Vector& x, const Vector&, const EnergyRequest& request) const {
  if (request.value) *request.value -= factor * forces_.dot(x);
  if (request.gradient) *request.gradient -= factor * forces_;
}

std::vector<RodOutput> RodSceneModel::outputs() const {
  std::vector<RodOutput> out;
  for (std::size_t k = 0; k < rods.size(); ++k) out.push_back({rods[k].get(), blocks[k]});
  return out;
}

bool is_rod_scene(const std::string& path) {
  std::ifstream f(path);
  if (!f) return false;
  const json j = json::parse(f, nullptr, false);
  return j.is_object() && j.contains("rods");
}

RodSceneSpec parse_rod_scene(const json& scene) {
  RodSceneSpec spec;
  if (!scene.contains("rods") || !scene["rods"].is_array() || scene["rods"].empty())
    fail("rods", "expected a non-empty array of rods");
  if (scene.contains("gravity")) spec.gravity = vec3(scene["gravity"], "gravity");
  constexpr int kMaxInt = std::numeric_limits<int>::max();
  spec.load_steps = integer(scene, "load_steps", "scene", 1, 1, kMaxInt);
  spec.max_newton_iterations = integer(scene, "max_newton_iterations", "scene", 200, 1, kMaxInt);
  for (std::size_t k = 0; k < scene["rods"].size(); ++k) {
    const json& r = scene["rods"][k];
    const std::string where = "rods[" + std::to_string(k) + "]";
    if (!r.is_object()) fail(where, "expected an object");
    RodSpec rod;
    if (r.contains("name") && !r["name"].is_string()) fail(where + ".name", "expected a string");
    rod.name = r.value("name", "rod" + std::to_string(k));
    rod.points = points_of(r, where);
    rod.closed = boolean(r, "closed", where, r.contains("circle"));
    if (rod.closed && r.contains("line")) fail(where + ".closed", "a 'line' cannot be closed");
    rod.closing_twist = number(r, "closing_twist", where, 0.0);
    if (rod.closing_twist != 0.0 && !rod.closed) fail(where + ".closing_twist", "only for closed rods");
    if (!std::isfinite(rod.closing_twist)) fail(where + ".closing_twist", "must be finite");
    if (r.contains("rest_shape")) {
      if (r["rest_shape"] == "drawn")
        rod.straight_rest = false;
      else if (r["rest_shape"] == "straight")
        rod.straight_rest = true;
      else
        fail(where + ".rest_shape", "expected \"drawn\" or \"straight\"");
    }
    const json cs = object_member(r, "cross_section", where);
    if (cs.contains("shape") && !cs["shape"].is_string())
      fail(where + ".cross_section.shape", "expected a string");
    try {
      rod.material.section.shape = cross_section_shape_from_string(cs.value("shape", std::string("circle")));
    } catch (const std::invalid_argument& e) {
      fail(where + ".cross_section.shape", e.what());
    }
    rod.material.section.aspect = number(cs, "aspect", where + ".cross_section", 1.0);
    rod.material.radius = number(cs, "radius", where + ".cross_section");
    const json mat = object_member(r, "material", where);
    rod.material.youngs_modulus = number(mat, "youngs_modulus", where + ".material");
    rod.material.shear_modulus =
        number(mat, "shear_modulus", where + ".material", rod.material.youngs_modulus / (2.0 * 1.3));
    rod.density = number(mat, "density", where + ".material", 0.0);
    try {
      rod.material.validate();
    } catch (const std::invalid_argument& e) {
      fail(where, e.what());
    }
    for (const auto& c : r.value("clamp", json::array())) {
      if (c == "first")
        rod.clamped.push_back(RodEnd::first);
      else if (c == "last")
        rod.clamped.push_back(RodEnd::last);
      else
        fail(where + ".clamp", "expected \"first\" or \"last\"");
    }
    if (rod.closed && !rod.clamped.empty()) fail(where + ".clamp", "a closed rod has no ends (use clamp_edges)");
    const int nv = static_cast<int>(rod.points.rows());
    const int ne = rod.closed ? nv : nv - 1;
    for (const auto& e : r.value("clamp_edges", json::array())) {
      if (!e.is_number_integer() || e.get<std::int64_t>() < 0 || e.get<std::int64_t>() >= ne)
        fail(where + ".clamp_edges", "edge out of range");
      rod.clamped_edges.push_back(e.get<int>());
    }
    for (const auto& v : r.value("pin", json::array())) {
      if (!v.is_number_integer() || v.get<std::int64_t>() < 0 || v.get<std::int64_t>() >= nv)
        fail(where + ".pin", "vertex out of range");
      rod.pinned.push_back(v.get<int>());
    }
    for (const auto& l : r.value("point_loads", json::array())) {
      if (!l.is_object()) fail(where + ".point_loads", "expected objects with vertex and force");
      const int v = integer(l, "vertex", where + ".point_loads", {}, 0, nv - 1);
      rod.point_loads.push_back({v, vec3(l.value("force", json()), where + ".point_loads.force")});
    }
    for (const auto& m : r.value("twisting_moments", json::array())) {
      if (!m.is_object()) fail(where + ".twisting_moments", "expected objects with edge and moment");
      const int e = integer(m, "edge", where + ".twisting_moments", {}, 0, ne - 1);
      rod.twisting_moments.emplace_back(e, number(m, "moment", where + ".twisting_moments"));
    }
    spec.rods.push_back(std::move(rod));
  }
  return spec;
}

RodSceneModel build_rod_model(const RodSceneSpec& spec) {
  int num_positions = 0, num_twists = 0;
  for (const auto& r : spec.rods)
    num_positions += 3 * static_cast<int>(r.points.rows()),
        num_twists += static_cast<int>(r.points.rows()) - (r.closed ? 0 : 1);
  RodSceneModel m;
  m.model = std::make_unique<Model>(num_positions + num_twists);
  Model& model = *m.model;
  m.rest = Vector::Zero(model.num_dofs());
  Vector forces = Vector::Zero(model.num_dofs());
  std::vector<int> fixed;
  int position_offset = 0, twist_offset = num_positions;
  for (const auto& r : spec.rods) {
    auto rod = std::make_shared<DiscreteRod>(r.points, position_offset, twist_offset, Eigen::Vector3d::Zero(),
                                             r.closed ? RodTopology::closed : RodTopology::open);
    m.first_vertex.push_back(position_offset / 3);
    position_offset += 3 * rod->num_vertices();
    twist_offset += rod->num_edges();
    m.blocks.push_back(add_rod_parameters(model.parameter_layout(), *rod, r.name));
    rod->write_rest_state(m.rest);
    m.rods.push_back(rod);
  }
  m.p = Vector::Zero(model.parameter_layout().size());
  for (std::size_t k = 0; k < m.rods.size(); ++k) {
    const RodSpec& r = spec.rods[k];
    const auto& rod = m.rods[k];
    const RodParameterBlocks& blocks = m.blocks[k];
    write_rod_parameters(*rod, blocks, r.material, m.p);
    if (r.straight_rest) {
      m.p.segment(blocks.rest_curvature, 2 * rod->num_interior()).setZero();
      m.p.segment(blocks.rest_twist, rod->num_interior()).setZero();
    }
    // Ends joined after twisting by closing_twist: m - mbar = closing_twist / n at each stencil.
    m.p.segment(blocks.rest_twist, rod->num_interior()).array() -= r.closing_twist / rod->num_interior();
    model.add(std::make_unique<RodStretchingTerm>(rod, r.material.section, blocks));
    model.add(std::make_unique<RodBendingTerm>(rod, r.material.section, blocks));
    model.add(std::make_unique<RodTwistingTerm>(rod, r.material.section, blocks));
    if (r.density > 0.0)
      add_gravity_forces(*rod,
                         lumped_vertex_masses(*rod, r.material.section, r.density,
                                              m.p.segment(blocks.radius, rod->num_edges()),
                                              m.p.segment(blocks.rest_length, rod->num_edges())),
                         spec.gravity, forces);
    for (const auto& l : r.point_loads) add_point_load(*rod, l.vertex, l.force, forces);
    for (const auto& [edge, moment] : r.twisting_moments) add_twisting_moment(*rod, edge, moment, forces);
    for (RodEnd end : r.clamped)
      for (int d : clamped_end_dofs(*rod, end)) fixed.push_back(d);
    for (int e : r.clamped_edges) {
      for (int d : pinned_vertex_dofs(*rod, e)) fixed.push_back(d);
      for (int d : pinned_vertex_dofs(*rod, rod->edge_end(e))) fixed.push_back(d);
      fixed.push_back(rod->twist_dof(e));
    }
    for (int v : r.pinned)
      for (int d : pinned_vertex_dofs(*rod, v)) fixed.push_back(d);
  }
  std::sort(fixed.begin(), fixed.end());
  fixed.erase(std::unique(fixed.begin(), fixed.end()), fixed.end());
  model.set_elimination(Elimination::dirichlet(fixed, m.rest));
  m.load = &model.add(std::make_unique<RodLoadTerm>(forces));
  return m;
}

RodSimulation simulate_rods(const RodSceneSpec& spec, const std::string& out_dir, std::ostream* log) {
  RodSceneModel m = build_rod_model(spec);
  Model& model = *m.model;
  auto& load = *m.load;
  auto& rods = m.rods;
  const Vector& p = m.p;
  const Vector& rest = m.rest;
  const std::vector<RodOutput> outputs = m.outputs();
  RodSimulation result;
  NewtonOptions options;
  options.max_iterations = spec.max_newton_iterations;
  NewtonSolver newton(model, options);
  Vector y = model.elimination().restrict_state(rest);
  result.converged = true;
  // Load steps; the reference frames move to each converged state (time-parallel transport).
  for (int step = 1; step <= spec.load_steps && result.converged; ++step) {
    load.factor = static_cast<double>(step) / spec.load_steps;
    const NewtonResult r = newton.solve(p, y);
    result.converged = r.converged();
    result.newton_iterations += r.iterations;
    result.state = model.state(y, p);
    for (auto& rod : rods) rod->update_reference_frames(result.state);
    if (log) *log << "load step " << step << "/" << spec.load_steps << ": " << r.report() << "\n";
  }
  std::filesystem::create_directories(out_dir);
  result.vtu_path = (std::filesystem::path(out_dir) / "rods.vtu").string();
  write_rods_vtu(result.vtu_path, outputs, result.state, p);
  if (log) *log << "wrote " << result.vtu_path << "\n";
  return result;
}

bool simulate_rod_scene_file(const std::string& path, const std::string& out_dir, std::ostream& log) {
  std::ifstream f(path);
  if (!f) throw SceneError(path + ": cannot open the scene file");
  json document;
  try {
    document = json::parse(f);
  } catch (const json::exception& e) {
    throw SceneError(path + ": invalid JSON: " + e.what());
  }
  const RodSceneSpec spec = parse_rod_scene(document);
  return simulate_rods(spec, out_dir, &log).converged;
}

}  // namespace tailor
