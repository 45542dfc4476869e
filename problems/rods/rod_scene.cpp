#include "problems/rods/rod_scene.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include "forward/core/elimination.hpp"
#include "forward/dynamics/inertia_term.hpp"
#include "forward/dynamics/mass_operator.hpp"
#include "forward/rods/bending_term.hpp"
#include "forward/rods/stretching_term.hpp"
#include "forward/rods/twisting_moment_term.hpp"
#include "forward/rods/twisting_term.hpp"
#include "forward/solve/newton.hpp"
#include "problems/fem/scene.hpp"
#include "problems/fem/scene_parsing.hpp"
#include "problems/json_text.hpp"
#include "problems/report_file.hpp"
#include "problems/report_header.hpp"
#include "problems/rods/rod_vtu.hpp"
#include "problems/scene_node.hpp"

namespace tailor {

void RodLoadTerm::evaluate(const Vector& x, const Vector&, const EnergyRequest& request) const {
  if (request.value) *request.value -= factor * forces_.dot(x);
  if (request.gradient) *request.gradient -= factor * forces_;
}

std::vector<RodOutput> RodSceneModel::outputs() const {
  std::vector<RodOutput> out;
  for (std::size_t k = 0; k < rods.size(); ++k) out.push_back({rods[k].get(), blocks[k]});
  return out;
}

namespace {

// More vertices than any rod needs; the points are allocated while parsing.
constexpr int kMaxRodVertices = 10'000'000;

// An integer in [lo, hi]; anything else is refused (casting it to int would be undefined).
int integer_between(const SceneNode& node, int lo, int hi) {
  const double v = node.number();
  if (!(v >= lo && v <= hi) || v != std::floor(v))
    node.fail("expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
              describe_json(node.json()));
  return static_cast<int>(v);
}

double number_or(const SceneNode& node, const char* key, double fallback) {
  const auto member = node.find(key);
  return member ? member->number() : fallback;
}

Eigen::Vector3d vec3(const SceneNode& node) { return Eigen::Vector3d(node.vector(3)); }

// Fails at member `key` of `node` also when it is absent: a key the rest of the scene requires.
[[noreturn]] void fail_at_member(const SceneNode& node, const char* key, const std::string& what) {
  if (const auto member = node.find(key)) member->fail(what);
  SceneNode(node.json(), node.source(), node.path() + "." + key).fail(what);
}

Eigen::MatrixX3d listed_points(const SceneNode& node) {
  const std::vector<SceneNode> points = node.items();
  if (points.size() < 3) node.fail("expected at least 3 points, got " + std::to_string(points.size()));
  Eigen::MatrixX3d x(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    x.row(static_cast<Eigen::Index>(i)) = vec3(points[i]).transpose();
  return x;
}

// n vertices from `from` to `to`; with the ends at edge midpoints the first and last edges
// straddle them instead: vertex i at s = (i - 1/2) h, h = |to - from| / (n - 2).
Eigen::MatrixX3d line_points(const SceneNode& node, bool ends_at_edge_midpoints) {
  node.expect_keys({"from", "to", "vertices"});
  const Eigen::Vector3d a = vec3(node.at("from")), b = vec3(node.at("to"));
  const int n = integer_between(node.at("vertices"), 3, kMaxRodVertices);
  Eigen::MatrixX3d x(n, 3);
  for (int i = 0; i < n; ++i) {
    const double s = ends_at_edge_midpoints ? (i - 0.5) / (n - 2.0) : i / (n - 1.0);
    x.row(i) = (a + (b - a) * s).transpose();
  }
  return x;
}

Eigen::MatrixX3d circle_points(const SceneNode& node) {
  node.expect_keys({"center", "radius", "normal", "vertices", "start_angle"});
  const auto center = node.find("center");
  const Eigen::Vector3d c = center ? vec3(*center) : Eigen::Vector3d::Zero();
  const auto normal = node.find("normal");
  const Eigen::Vector3d z = normal ? vec3(*normal) : Eigen::Vector3d::UnitZ();
  if (!(z.norm() > 0.0)) normal->fail("must be non-zero");
  const double R = node.at("radius").positive();
  const double start = number_or(node, "start_angle", 0.0);
  const int n = integer_between(node.at("vertices"), 3, kMaxRodVertices);
  // (u, v): an orthonormal basis of the circle's plane.
  const Eigen::Vector3d w = z.normalized();
  Eigen::Index k = 0;
  w.cwiseAbs().minCoeff(&k);
  const Eigen::Vector3d u = (Eigen::Vector3d::Unit(k) - w[k] * w).normalized(), v = w.cross(u);
  Eigen::MatrixX3d x(n, 3);
  for (int i = 0; i < n; ++i) {
    const double phi = start + 2.0 * M_PI * i / n;
    x.row(i) = (c + R * (std::cos(phi) * u + std::sin(phi) * v)).transpose();
  }
  return x;
}

Eigen::MatrixX3d points_of(const SceneNode& rod, bool ends_at_edge_midpoints) {
  const int given = int{rod.has("points")} + int{rod.has("line")} + int{rod.has("circle")};
  if (given == 0) rod.fail("needs 'points', 'line' or 'circle'");
  if (given > 1) rod.fail("give only one of 'points', 'line' and 'circle'");
  if (const auto points = rod.find("points")) return listed_points(*points);
  if (const auto line = rod.find("line")) return line_points(*line, ends_at_edge_midpoints);
  return circle_points(rod.at("circle"));
}

// closed, closing_twist and rest_shape: how the drawn points are joined and what is at rest.
void parse_rod_shape(const SceneNode& node, RodSpec& rod) {
  const auto closed = node.find("closed");
  rod.closed = closed ? closed->boolean() : node.has("circle");
  if (rod.closed && node.has("line")) closed->fail("a 'line' cannot be closed");
  rod.closing_twist = number_or(node, "closing_twist", 0.0);
  if (rod.closing_twist != 0.0 && !rod.closed) node.at("closing_twist").fail("only for closed rods");
  if (const auto rest = node.find("rest_shape"))
    rod.straight_rest = rest->choice({"drawn", "straight"}) == "straight";
  if (rod.closed && rod.ends_at_edge_midpoints) node.at("ends").fail("a closed rod has no ends");
}

// "ends": where the rod's ends are, "vertices" (default: its first and last vertex) or
// "edge_midpoints" (the midpoints of its first and last edges).
bool parse_rod_ends(const SceneNode& node) {
  const auto ends = node.find("ends");
  return ends && ends->choice({"vertices", "edge_midpoints"}) == "edge_midpoints";
}

void parse_cross_section(const SceneNode& node, RodMaterial& material) {
  node.expect_keys({"shape", "radius", "aspect"});
  const auto shape = node.find("shape");
  try {
    material.section.shape = cross_section_shape_from_string(shape ? shape->string() : "circle");
  } catch (const std::invalid_argument& e) {
    shape->fail(e.what());
  }
  if (const auto aspect = node.find("aspect")) material.section.aspect = aspect->positive();
  material.radius = node.at("radius").positive();
  try {
    material.section.validate();  // a circle's aspect is 1
  } catch (const std::invalid_argument& e) {
    node.fail(e.what());
  }
}

void parse_rod_material(const SceneNode& node, RodSpec& rod) {
  node.expect_keys({"youngs_modulus", "shear_modulus", "density"});
  rod.material.youngs_modulus = node.at("youngs_modulus").positive();
  const auto shear = node.find("shear_modulus");
  rod.material.shear_modulus = shear ? shear->positive() : rod.material.youngs_modulus / (2.0 * 1.3);
  rod.density = number_or(node, "density", 0.0);
}

void parse_rod_supports(const SceneNode& node, RodSpec& rod) {
  const int nv = static_cast<int>(rod.points.rows()), ne = rod.closed ? nv : nv - 1;
  if (const auto clamp = node.find("clamp")) {
    for (const SceneNode& end : clamp->items())
      rod.clamped.push_back(end.choice({"first", "last"}) == "first" ? RodEnd::first : RodEnd::last);
    if (rod.closed && !rod.clamped.empty()) clamp->fail("a closed rod has no ends (use clamp_edges)");
  }
  if (const auto edges = node.find("clamp_edges"))
    for (const SceneNode& edge : edges->items())
      rod.clamped_edges.push_back(integer_between(edge, 0, ne - 1));
  if (const auto pins = node.find("pin"))
    for (const SceneNode& vertex : pins->items()) rod.pinned.push_back(integer_between(vertex, 0, nv - 1));
}

void parse_rod_loads(const SceneNode& node, RodSpec& rod) {
  const int nv = static_cast<int>(rod.points.rows()), ne = rod.closed ? nv : nv - 1;
  if (const auto loads = node.find("point_loads"))
    for (const SceneNode& load : loads->items()) {
      load.expect_keys({"vertex", "end", "force"});
      const Eigen::Vector3d force = vec3(load.at("force"));
      if (load.has("vertex") == load.has("end")) load.fail("give exactly one of 'vertex' and 'end'");
      if (const auto vertex = load.find("vertex")) {
        rod.point_loads.push_back({integer_between(*vertex, 0, nv - 1), force});
        continue;
      }
      const SceneNode end = load.at("end");
      if (rod.closed) end.fail("a closed rod has no ends");
      const bool first = end.choice({"first", "last"}) == "first";
      if (!rod.ends_at_edge_midpoints) {
        rod.point_loads.push_back({first ? 0 : nv - 1, force});
        continue;
      }
      // At the end edge's midpoint: half on each of its vertices.
      rod.point_loads.push_back({first ? 0 : nv - 2, 0.5 * force});
      rod.point_loads.push_back({first ? 1 : nv - 1, 0.5 * force});
    }
  if (const auto moments = node.find("twisting_moments"))
    for (const SceneNode& moment : moments->items()) {
      moment.expect_keys({"edge", "moment"});
      rod.twisting_moments.emplace_back(integer_between(moment.at("edge"), 0, ne - 1),
                                        moment.at("moment").number());
    }
}

RodSpec parse_rod(const SceneNode& node, std::size_t k) {
  node.expect_keys({"name", "points", "line", "circle", "closed", "closing_twist", "rest_shape", "ends",
                    "clamp_edges", "cross_section", "material", "clamp", "pin", "point_loads",
                    "twisting_moments"});
  RodSpec rod;
  const auto name = node.find("name");
  rod.name = name ? name->string() : "rod" + std::to_string(k);
  rod.ends_at_edge_midpoints = parse_rod_ends(node);
  rod.points = points_of(node, rod.ends_at_edge_midpoints);
  parse_rod_shape(node, rod);
  parse_cross_section(node.at("cross_section"), rod.material);
  parse_rod_material(node.at("material"), rod);
  parse_rod_supports(node, rod);
  parse_rod_loads(node, rod);
  return rod;
}

// A joint member {"rod": name or index, "vertex": v, "first" or "last"}: (rod index, vertex).
std::pair<int, int> parse_joint_member(const SceneNode& node, const std::vector<RodSpec>& rods) {
  node.expect_keys({"rod", "vertex"});
  const SceneNode rod_node = node.at("rod");
  int rod = -1;
  if (rod_node.is_string()) {
    const std::string name = rod_node.string();
    for (std::size_t q = 0; q < rods.size(); ++q)
      if (rods[q].name == name) rod = static_cast<int>(q);
    if (rod < 0) rod_node.fail("no rod named '" + name + "'");
  } else {
    rod = integer_between(rod_node, 0, static_cast<int>(rods.size()) - 1);
  }
  const int nv = static_cast<int>(rods[static_cast<std::size_t>(rod)].points.rows());
  const SceneNode vertex = node.at("vertex");
  if (vertex.is_string()) return {rod, vertex.choice({"first", "last"}) == "first" ? 0 : nv - 1};
  return {rod, integer_between(vertex, 0, nv - 1)};
}

// The members must be different rods meeting at one drawn point (within 1e-9 of `extent`).
RodJointSpec parse_joint(const SceneNode& node, const std::vector<RodSpec>& rods, double extent) {
  node.expect_keys({"type", "rods"});
  RodJointSpec joint;
  if (const auto type = node.find("type")) joint.rigid = type->choice({"pinned", "rigid"}) == "rigid";
  const SceneNode members = node.at("rods");
  const std::vector<SceneNode> items = members.items();
  if (items.size() < 2) members.fail("expected at least 2 members {\"rod\": name or index, \"vertex\": v}");
  for (const SceneNode& item : items) {
    const auto [rod, vertex] = parse_joint_member(item, rods);
    for (const auto& [r0, v0] : joint.members) {
      if (r0 == rod) item.fail("a joint joins different rods (rod " + std::to_string(rod) + " twice)");
      const double gap = (rods[static_cast<std::size_t>(r0)].points.row(v0) -
                          rods[static_cast<std::size_t>(rod)].points.row(vertex))
                             .norm();
      if (gap > 1e-9 * extent)
        item.fail("the vertex is " + std::to_string(gap) + " away from the joint's first vertex");
    }
    joint.members.emplace_back(rod, vertex);
  }
  return joint;
}

std::vector<RodJointSpec> parse_joints(const SceneNode& node, const std::vector<RodSpec>& rods) {
  double extent = 0.0;
  for (const auto& r : rods)
    extent = std::max(extent, (r.points.colwise().maxCoeff() - r.points.colwise().minCoeff()).norm());
  std::vector<RodJointSpec> joints;
  for (const SceneNode& item : node.items()) joints.push_back(parse_joint(item, rods, extent));
  return joints;
}

// The "dynamics" section of docs/dynamics.md, less what rods lack: damping, trajectory
// objectives, a consistent mass, rotary inertia of rigid joints.
DynamicsSpec parse_rod_dynamics(const SceneNode& root, const RodSceneSpec& spec) {
  const SceneNode node = root.at("dynamics");
  // Refused before the shared parser reads them: an objective's vertex selectors are a mesh's.
  if (node.has("rayleigh")) node.at("rayleigh").fail("Rayleigh damping is not implemented for rod scenes");
  if (node.has("objective"))
    node.at("objective").fail("trajectory objectives are not implemented for rod scenes");
  if (node.has("reduction")) node.at("reduction").fail("reduced dynamics is for FEM scenes (docs/reduction.md)");
  DynamicsSpec d = parse_dynamics_section(node, ".");
  if (node.has("mass") && node.at("mass").string() != "lumped")
    node.at("mass").fail("rods have a lumped mass only (\"lumped\")");
  if (d.initial_velocity && d.initial_velocity->size() != 3)
    node.at("initial_velocity").fail("expected 3 components");
  if (root.has("load_steps"))
    root.at("load_steps").fail("not used with a dynamics section (loads act from t = 0)");
  const std::vector<SceneNode> rods = root.at("rods").items();
  for (std::size_t k = 0; k < spec.rods.size(); ++k) {
    if (!(spec.rods[k].density > 0.0))
      fail_at_member(rods[k].at("material"), "density", "a dynamic scene needs a positive density");
    if (spec.rods[k].ends_at_edge_midpoints)
      rods[k].at("ends").fail("ends at edge midpoints are not implemented with a dynamics section (the lumped "
                              "masses of the end edges are whole)");
  }
  d.lumping = MassLumping::lumped;
  for (std::size_t k = 0; k < spec.joints.size(); ++k)
    if (spec.joints[k].rigid)
      root.at("joints").items()[k].at("type").fail(
          "rigid joints are not implemented with a dynamics section (the joint has no rotary inertia)");
  return d;
}

}  // namespace

RodSceneSpec parse_rod_scene(const SceneNode& root) {
  // Next to a mesh the static scene's keys are the FEM body's (simulate_rods_with_fem).
  if (root.has("mesh"))
    root.expect_keys({"name", "description", "rods", "joints", "gravity", "load_steps",
                      "max_newton_iterations", "dynamics", "inverse", "mesh", "materials", "dirichlet",
                      "loads", "solver"});
  else
    root.expect_keys({"name", "description", "rods", "joints", "gravity", "load_steps",
                      "max_newton_iterations", "dynamics", "inverse"});
  if (const auto name = root.find("name")) name->string();
  if (const auto description = root.find("description")) description->string();
  RodSceneSpec spec;
  const SceneNode rods = root.at("rods");
  const std::vector<SceneNode> items = rods.items();
  if (items.empty()) rods.fail("expected a non-empty array of rods");
  for (std::size_t k = 0; k < items.size(); ++k) spec.rods.push_back(parse_rod(items[k], k));
  if (const auto gravity = root.find("gravity")) spec.gravity = vec3(*gravity);
  constexpr int kMaxInt = std::numeric_limits<int>::max();
  if (const auto steps = root.find("load_steps")) spec.load_steps = integer_between(*steps, 1, kMaxInt);
  if (const auto newton = root.find("max_newton_iterations"))
    spec.max_newton_iterations = integer_between(*newton, 1, kMaxInt);
  if (const auto joints = root.find("joints")) spec.joints = parse_joints(*joints, spec.rods);
  if (root.has("dynamics")) spec.dynamics = parse_rod_dynamics(root, spec);
  return spec;
}

RodSceneSpec parse_rod_scene(const nlohmann::json& scene, const std::string& source) {
  return parse_rod_scene(SceneNode(scene, source, ""));
}

namespace {

// x = x0 + S y with the fixed DOFs at their values and each group of tied DOFs one unknown (the
// groups' DOFs must have equal values in `values`). A group with a fixed DOF is fixed.
Elimination tied_dirichlet(const std::vector<int>& fixed, const std::vector<std::vector<int>>& ties,
                           const Vector& values) {
  const int n = static_cast<int>(values.size());
  std::vector<int> parent(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) parent[static_cast<std::size_t>(i)] = i;
  auto find = [&](int i) {
    while (parent[static_cast<std::size_t>(i)] != i)
      i = parent[static_cast<std::size_t>(i)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
    return i;
  };
  for (const auto& group : ties)
    for (std::size_t k = 1; k < group.size(); ++k) {
      const int a = find(group[0]), b = find(group[k]);
      if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
    }
  std::vector<char> root_fixed(static_cast<std::size_t>(n), 0);
  for (int d : fixed) root_fixed[static_cast<std::size_t>(find(d))] = 1;
  std::vector<int> column(static_cast<std::size_t>(n), -1);
  Vector x0 = Vector::Zero(n);
  Triplets triplets;
  int columns = 0;
  for (int i = 0; i < n; ++i) {
    const int root = find(i);
    if (root_fixed[static_cast<std::size_t>(root)]) {
      x0[i] = values[i];
      continue;
    }
    if (column[static_cast<std::size_t>(root)] < 0) column[static_cast<std::size_t>(root)] = columns++;
    triplets.emplace_back(i, column[static_cast<std::size_t>(root)], 1.0);
  }
  SparseMatrix S(n, columns);
  S.setFromTriplets(triplets.begin(), triplets.end());
  return Elimination(std::move(x0), std::move(S));
}

}  // namespace

RodSceneModel build_rod_model(const RodSceneSpec& spec, const RodModelPrefix& prefix) {
  int num_positions = 0, num_twists = 0, num_rigid = 0;
  for (const auto& r : spec.rods)
    num_positions += 3 * static_cast<int>(r.points.rows()),
        num_twists += static_cast<int>(r.points.rows()) - (r.closed ? 0 : 1);
  for (const auto& joint : spec.joints) num_rigid += joint.rigid ? 1 : 0;
  if (prefix.dofs > 0 && prefix.values.size() != prefix.dofs)
    throw std::invalid_argument("build_rod_model: prefix values need one entry per prefix DOF");
  RodSceneModel m;
  m.model = std::make_unique<Model>(prefix.dofs + num_positions + num_twists + 3 * num_rigid);
  Model& model = *m.model;
  for (const auto& [name, size] : prefix.parameter_blocks) model.parameter_layout().add(name, size);
  m.rest = Vector::Zero(model.num_dofs());
  if (prefix.dofs > 0) m.rest.head(prefix.dofs) = prefix.values;
  Vector forces = Vector::Zero(model.num_dofs());
  std::vector<int> fixed = prefix.fixed_dofs;
  int position_offset = prefix.dofs, twist_offset = prefix.dofs + num_positions;
  for (const auto& r : spec.rods) {
    auto rod = std::make_shared<DiscreteRod>(r.points, position_offset, twist_offset, Eigen::Vector3d::Zero(),
                                             r.closed ? RodTopology::closed : RodTopology::open);
    m.first_vertex.push_back((position_offset - prefix.dofs) / 3);  // within the rods part
    position_offset += 3 * rod->num_vertices();
    twist_offset += rod->num_edges();
    m.blocks.push_back(add_rod_parameters(model.parameter_layout(), *rod, r.name));
    rod->write_rest_state(m.rest);
    m.rods.push_back(rod);
  }
  m.p = Vector::Zero(model.parameter_layout().size());
  std::vector<RodBendingTerm*> bending;
  std::vector<RodTwistingTerm*> twisting;
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
    bending.push_back(&model.add(std::make_unique<RodBendingTerm>(rod, r.material.section, blocks)));
    twisting.push_back(&model.add(std::make_unique<RodTwistingTerm>(rod, r.material.section, blocks)));
    if (r.density > 0.0) {
      Eigen::VectorXd masses = lumped_vertex_masses(*rod, r.material.section, r.density,
                                                    m.p.segment(blocks.radius, rod->num_edges()),
                                                    m.p.segment(blocks.rest_length, rod->num_edges()));
      if (r.ends_at_edge_midpoints)  // half of each end edge lies beyond the rod's end
        for (int j : {0, rod->num_edges() - 1}) {
          const double radius = m.p[blocks.radius + j];
          const double quarter =
              0.25 * r.density * r.material.section.area_coefficient() * radius * radius * m.p[blocks.rest_length + j];
          masses[j] -= quarter;
          masses[j + 1] -= quarter;
        }
      add_gravity_forces(*rod, masses, spec.gravity, forces);
    }
    for (const auto& l : r.point_loads) add_point_load(*rod, l.vertex, l.force, forces);
    if (!r.twisting_moments.empty())  // a potential of the state, not a force on theta (see the term)
      m.twisting_moments.push_back(&model.add(std::make_unique<RodTwistingMomentTerm>(rod, r.twisting_moments)));
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
  // Pinned joints: the members' position DOFs tied (free rotation: frames and twists stay apart).
  std::vector<std::vector<int>> ties;
  for (const RodJointSpec& joint : spec.joints)
    for (int c = 0; c < 3; ++c) {
      std::vector<int> group;
      for (const auto& [rod, vertex] : joint.members)
        group.push_back(m.rods[static_cast<std::size_t>(rod)]->position_dof(vertex, c));
      ties.push_back(std::move(group));
    }
  if (ties.empty())
    model.set_elimination(Elimination::dirichlet(fixed, m.rest));
  else {
    // The members coincide to 1e-9 of the scene's size: give them the first member's position.
    for (const auto& group : ties)
      for (std::size_t k = 1; k < group.size(); ++k) m.rest[group[k]] = m.rest[group[0]];
    model.set_elimination(tied_dirichlet(fixed, ties, m.rest));
  }
  // Rigid joints: a rotation vector per joint (after all twists, zero at rest), each member edge
  // coupled to the joint's frame, stress-free in the drawn state.
  int rotation_offset = prefix.dofs + num_positions + num_twists;
  for (const RodJointSpec& joint : spec.joints) {
    if (!joint.rigid) continue;
    auto term = std::make_unique<RodRigidJointTerm>(rotation_offset);
    rotation_offset += 3;
    for (const auto& [rod_index, vertex] : joint.members) {
      const auto& rod = m.rods[static_cast<std::size_t>(rod_index)];
      const RodSpec& r = spec.rods[static_cast<std::size_t>(rod_index)];
      const RodParameterBlocks& blocks = m.blocks[static_cast<std::size_t>(rod_index)];
      std::vector<int> edges;
      const int nv = rod->num_vertices();
      if (rod->closed())
        edges = {(vertex + nv - 1) % nv, vertex};
      else {
        if (vertex > 0) edges.push_back(vertex - 1);
        if (vertex < nv - 1) edges.push_back(vertex);
      }
      // At an interior vertex the two ghost stencils through the joint replace the rod's own
      // bending and twisting stencil (in series they have its stiffness; keeping it would
      // double the vertex's stiffness).
      if (edges.size() == 2) {
        bending[static_cast<std::size_t>(rod_index)]->omit_stencil(edges[0]);
        twisting[static_cast<std::size_t>(rod_index)]->omit_stencil(edges[0]);
      }
      for (int e : edges)
        term->add_member(
            rod, e,
            rigid_joint_stiffness(r.material.section, r.material.youngs_modulus, r.material.shear_modulus,
                                  m.p[blocks.radius + e], m.p[blocks.rest_length + e]),
            m.rest);
    }
    m.rigid_joints.push_back(&model.add(std::move(term)));
  }
  m.load = &model.add(std::make_unique<RodLoadTerm>(forces));
  return m;
}

namespace {

nlohmann::ordered_json scene_summary(const RodSceneSpec& spec, const RodSceneModel& m) {
  nlohmann::ordered_json rods = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < m.rods.size(); ++k)
    rods.push_back({{"name", spec.rods[k].name},
                    {"vertices", m.rods[k]->num_vertices()},
                    {"edges", m.rods[k]->num_edges()},
                    {"closed", m.rods[k]->closed()}});
  return {{"source", spec.source},
          {"rods", rods},
          {"dofs", m.model->num_dofs()},
          {"free_dofs", m.model->elimination().num_free()}};
}

// Energy of every term at x (terms of the same name summed), and their total.
nlohmann::ordered_json energies(const Model& model, const Vector& x, const Vector& p, double* total) {
  nlohmann::ordered_json e = nlohmann::ordered_json::object();
  *total = 0.0;
  for (const auto& term : model.terms()) {
    const double v = term->value(x, p);
    const std::string name = term->name();
    e[name] = (e.contains(name) ? e[name].get<double>() : 0.0) + v;
    *total += v;
  }
  return e;
}

// Norm of the free part of the model's gradient at x (the equilibrium residual).
double free_residual(const Model& model, const Vector& x, const Vector& p) {
  Vector g = Vector::Zero(x.size());
  for (const auto& term : model.terms()) term->add_gradient(x, p, g);
  return (model.elimination().basis().transpose() * g).norm();
}

// A static solve needs every rod, or group of rods joined by joints, held against every rigid
// motion (a clamp, pins, clamped edges): the rods' energy resists only deformation, so a free
// group has no equilibrium (a free rod under gravity ran 200 Newton iterations with a growing
// residual). Throws SceneError naming the file, the rods and the free motions.
void require_held_rods(const RodSceneSpec& spec, const RodSceneModel& m) {
  const Elimination& elimination = m.model->elimination();
  std::vector<int> held;
  for (int i = 0; i < elimination.num_dofs(); ++i)
    if (elimination.row_begin()[static_cast<std::size_t>(i) + 1] == elimination.row_begin()[static_cast<std::size_t>(i)])
      held.push_back(i);
  const std::size_t n = m.rods.size();
  std::vector<std::size_t> group(n);
  for (std::size_t k = 0; k < n; ++k) group[k] = k;
  auto root = [&](std::size_t k) {
    while (group[k] != k) k = group[k];
    return k;
  };
  for (const RodJointSpec& joint : spec.joints)
    for (const auto& member : joint.members) {
      const std::size_t a = root(static_cast<std::size_t>(joint.members.front().first));
      const std::size_t b = root(static_cast<std::size_t>(member.first));
      group[std::max(a, b)] = std::min(a, b);
    }
  for (std::size_t first = 0; first < n; ++first) {
    if (root(first) != first) continue;
    std::vector<const DiscreteRod*> rods;
    std::string names;
    for (std::size_t k = first; k < n; ++k)
      if (root(k) == first) {
        rods.push_back(m.rods[k].get());
        names += std::string(names.empty() ? "" : " and ") + "rods[" + std::to_string(k) + "] (\"" +
                 spec.rods[k].name + "\")";
      }
    Eigen::Vector3d centre;
    const std::vector<rigid::FreeMotion> free = free_rod_motions(rods, m.rest, held, centre);
    if (free.empty()) continue;
    const bool one = rods.size() == 1;
    throw SceneError(spec.source + ": " + names + (one ? "" : ", joined") + ": the supports leave " +
                     (one ? "the rod" : "them") + " free to move rigidly (" +
                     rigid::describe_free_motions(free, centre) +
                     "), so a static solve has no equilibrium; clamp an end (\"clamp\"), pin vertices (\"pin\"), "
                     "clamp edges (\"clamp_edges\") or simulate it with a \"dynamics\" section");
  }
}

}  // namespace

RodSimulation simulate_rods(const RodSceneSpec& spec, const std::string& out_dir, std::ostream* log) {
  RodSceneModel m = build_rod_model(spec);
  return solve_rod_model(m, spec, out_dir, log);
}

RodSimulation solve_rod_model(RodSceneModel& m, const RodSceneSpec& spec, const std::string& out_dir,
                              std::ostream* log) {
  const auto start = std::chrono::steady_clock::now();
  Model& model = *m.model;
  auto& load = *m.load;
  auto& rods = m.rods;
  const Vector& p = m.p;
  const Vector& rest = m.rest;
  const std::vector<RodOutput> outputs = m.outputs();
  RodSimulation result;
  require_held_rods(spec, m);
  NewtonOptions options;
  options.max_iterations = spec.max_newton_iterations;
  NewtonSolver newton(model, options);
  Vector y = model.elimination().restrict_state(rest);
  result.converged = true;
  nlohmann::ordered_json steps = nlohmann::ordered_json::array();
  std::string message;
  NewtonResult last;
  // Load steps; the reference frames move to each converged state (time-parallel transport).
  for (int step = 1; step <= spec.load_steps && result.converged; ++step) {
    load.factor = static_cast<double>(step) / spec.load_steps;
    for (RodTwistingMomentTerm* moments : m.twisting_moments) moments->factor = load.factor;
    const NewtonResult r = newton.solve(p, y);
    last = r;
    result.converged = r.converged();
    result.newton_iterations += r.iterations;
    result.state = model.state(y, p);
    for (auto& rod : rods) rod->update_reference_frames(result.state);
    for (RodTwistingMomentTerm* moments : m.twisting_moments) moments->update_branches(result.state);
    steps.push_back({{"step", step},
                     {"load_factor", load.factor},
                     {"iterations", r.iterations},
                     {"initial_residual", r.initial_residual},
                     {"final_residual", r.final_residual},
                     {"converged", r.converged()}});
    if (!r.converged()) message = "load step " + std::to_string(step) + ": " + r.message;
    if (log) *log << "load step " << step << "/" << spec.load_steps << ": " << r.report() << "\n";
  }
  std::filesystem::create_directories(out_dir);
  result.vtu_path = (std::filesystem::path(out_dir) / "rods.vtu").string();
  write_rods_vtu(result.vtu_path, outputs, result.state, p);
  if (log) *log << "wrote " << result.vtu_path << "\n";
  nlohmann::ordered_json report;
  add_report_header(report);
  // The residual at the result, after the frames' update, must be what the last load step
  // converged to: the energy is one function of the state, whatever frames are stored. A
  // larger one means the solve converged on another function than the result's (as a
  // twisting moment written as a force on theta did): not converged, said so.
  const double residual = free_residual(model, result.state, p);
  if (result.converged) {
    const double scale = std::max(last.initial_residual, options.absolute_tolerance / options.relative_tolerance);
    const double allowed = std::max(10.0 * last.final_residual, std::sqrt(options.relative_tolerance) * scale);
    if (!(residual <= allowed)) {
      result.converged = false;
      std::ostringstream why;
      why << std::scientific << std::setprecision(3) << "the residual at the result (" << residual
          << ") is above what the last load step converged to (" << last.final_residual << ", at most "
          << allowed << " allowed): the equilibrium Newton found is not one of the energy at the result";
      message = why.str();
      if (log) *log << message << "\n";
    }
  }
  report["status"] = result.converged ? "converged" : "not_converged";
  report["message"] = message;
  report["scene"] = scene_summary(spec, m);
  double total = 0.0;
  report["energies"] = energies(model, result.state, p, &total);
  report["energy"] = total;
  report["residual"] = residual;
  report["load_steps"] = spec.load_steps;
  report["newton_iterations"] = result.newton_iterations;
  report["steps"] = steps;
  report["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report["vtu"] = "rods.vtu";
  result.report_path = write_report(out_dir, report);
  if (log) *log << "wrote " << result.report_path << "\n";
  return result;
}

Vector rod_scene_mass_diagonal(const RodSceneSpec& spec, const RodSceneModel& m) {
  Vector diagonal = Vector::Zero(m.model->num_dofs());
  for (std::size_t k = 0; k < m.rods.size(); ++k) {
    const DiscreteRod& rod = *m.rods[k];
    const RodParameterBlocks& b = m.blocks[k];
    add_rod_mass_diagonal(rod, spec.rods[k].material.section, spec.rods[k].density,
                          m.p.segment(b.radius, rod.num_edges()), m.p.segment(b.rest_length, rod.num_edges()),
                          diagonal);
  }
  return diagonal;
}

InertiaTerm& add_rod_inertia(RodSceneModel& m, Vector diagonal) {
  return m.model->add(
      std::make_unique<InertiaTerm>(std::make_shared<const MassOperator>(std::move(diagonal))));
}

RodDynamicsRun integrate_rods(RodSceneModel& m, const DynamicsSpec& dynamics, const Vector& x0,
                              const Vector& v0, const std::string& out_dir, std::ostream* log,
                              const RodStepObserver& observer) {
  const auto start = std::chrono::steady_clock::now();
  Model& model = *m.model;
  const Vector& p = m.p;
  m.load->factor = 1.0;
  for (RodTwistingMomentTerm* moments : m.twisting_moments) moments->factor = 1.0;
  for (auto& rod : m.rods) rod->update_reference_frames(x0);
  for (RodTwistingMomentTerm* moments : m.twisting_moments) moments->update_branches(x0);
  TimeIntegratorOptions options;
  options.scheme = dynamics.scheme;
  options.time_step = dynamics.time_step;
  TimeIntegrator integrator(model, options);
  RodDynamicsRun run;
  run.state = integrator.initial_state(x0, v0, p);
  const bool files = !out_dir.empty();
  const std::vector<RodOutput> outputs = m.outputs();
  const std::filesystem::path dir(out_dir);
  std::vector<double> frame_times;
  auto record = [&](const DynamicState& s) {
    run.time.push_back(s.time);
    run.kinetic_energy.push_back(integrator.kinetic_energy(s.v, p));
    run.potential_energy.push_back(integrator.potential_energy(s.x, p));
    if (observer) observer(s);
    if (files && (s.step % dynamics.output_every == 0 || s.step == dynamics.steps)) {
      char name[32];
      std::snprintf(name, sizeof name, "rods_%05d.vtu", s.step);
      std::filesystem::create_directories(dir / "frames");
      write_rods_vtu((dir / "frames" / name).string(), outputs, s.x, p);
      run.frames.push_back(std::string("frames/") + name);
      frame_times.push_back(s.time);
    }
  };
  record(run.state);
  run.completed = true;
  for (int step = 1; step <= dynamics.steps; ++step) {
    const NewtonResult r = integrator.step(run.state, p);
    run.newton_iterations += r.iterations;
    if (!r.converged()) {
      run.completed = false;
      run.message = "step " + std::to_string(step) + ": " + r.message;
      if (log) *log << run.message << "\n";
      break;
    }
    // Time-parallel transport of the reference frames to the new state.
    for (auto& rod : m.rods) rod->update_reference_frames(run.state.x);
    for (RodTwistingMomentTerm* moments : m.twisting_moments) moments->update_branches(run.state.x);
    run.steps = step;
    record(run.state);
  }
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (log)
    *log << "rod dynamics: " << run.steps << "/" << dynamics.steps << " steps of "
         << to_string(dynamics.scheme) << ", h = " << dynamics.time_step << ", " << run.newton_iterations
         << " Newton iterations, " << run.seconds << " s\n";
  if (!files) return run;
  std::filesystem::create_directories(dir);
  run.pvd_path = (dir / "rods.pvd").string();
  {
    std::ostringstream f;
    f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n";
    for (std::size_t k = 0; k < run.frames.size(); ++k)
      f << "    <DataSet timestep=\"" << frame_times[k] << "\" file=\"" << run.frames[k] << "\"/>\n";
    f << "  </Collection>\n</VTKFile>\n";
    write_text_file_atomically(run.pvd_path, f.str());
  }
  nlohmann::ordered_json report;
  add_report_header(report);
  report["status"] = run.completed ? "completed" : "failed";
  report["message"] = run.message;
  report["scheme"] = to_string(dynamics.scheme);
  report["time_step"] = dynamics.time_step;
  report["steps_requested"] = dynamics.steps;
  report["steps"] = run.steps;
  report["newton_iterations"] = run.newton_iterations;
  report["seconds"] = run.seconds;
  double total = 0.0;
  report["energies"] = energies(model, run.state.x, p, &total);  // includes the last step's inertia term
  report["kinetic_energy"] = run.kinetic_energy.back();
  report["potential_energy"] = run.potential_energy.back();
  report["energy_initial"] = run.kinetic_energy.front() + run.potential_energy.front();
  report["energy_final"] = run.kinetic_energy.back() + run.potential_energy.back();
  report["series"] = {
      {"time", run.time}, {"kinetic_energy", run.kinetic_energy}, {"potential_energy", run.potential_energy}};
  report["frames"] = run.frames;
  report["pvd"] = "rods.pvd";
  run.report_path = write_report(out_dir, report);
  if (log)
    *log << "wrote " << run.pvd_path << ", " << run.frames.size() << " frames and " << run.report_path
         << "\n";
  return run;
}

RodDynamicsRun simulate_rod_dynamics(const RodSceneSpec& spec, const std::string& out_dir,
                                     std::ostream* log) {
  if (!spec.dynamics) throw SceneError("rods scene: no dynamics section");
  RodSceneModel m = build_rod_model(spec);
  add_rod_inertia(m, rod_scene_mass_diagonal(spec, m));
  Vector v0 = Vector::Zero(m.rest.size());
  if (spec.dynamics->initial_velocity)
    for (const auto& rod : m.rods)
      for (int v = 0; v < rod->num_vertices(); ++v)
        v0.segment<3>(rod->position_dof(v, 0)) = *spec.dynamics->initial_velocity;
  // Fixed DOFs keep their values (zero velocity).
  const Vector x0 = m.model->elimination().expand(m.model->elimination().restrict_state(m.rest));
  const Elimination& elimination = m.model->elimination();
  for (int i = 0; i < elimination.num_dofs(); ++i)
    if (elimination.row_begin()[static_cast<std::size_t>(i) + 1] ==
        elimination.row_begin()[static_cast<std::size_t>(i)])
      v0[i] = 0.0;
  return integrate_rods(m, *spec.dynamics, x0, v0, out_dir, log);
}

bool simulate_rod_scene(const SceneNode& root, const std::string& directory, const std::string& out_dir,
                        std::ostream* log) {
  if (root.has("mesh")) return simulate_rods_with_fem(root, directory, out_dir, log).rods.converged;
  RodSceneSpec spec = parse_rod_scene(root);
  spec.source = root.source();
  if (spec.dynamics) return simulate_rod_dynamics(spec, out_dir, log).completed;
  return simulate_rods(spec, out_dir, log).converged;
}

}  // namespace tailor
