// Parsing the "interlocking" section (see interlocking_scene.hpp).
#include "problems/interlocking/interlocking_scene.hpp"

#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "forward/interlocking/cell_patterns.hpp"
#include "forward/interlocking/periodic_mesh_elements.hpp"
#include "problems/optimizer_section.hpp"
#include "problems/scene_error.hpp"

namespace tailor {
namespace {

// The radii of a torus among a node's keys (the caller checks the keys).
tori::TorusShape parse_shape_keys(const SceneNode& n) {
  tori::TorusShape s;
  s.major_radius = n.at("major_radius").positive();
  s.minor_radius = n.at("minor_radius").positive();
  if (auto r1 = n.find("minor_radius_1")) s.minor_radius_1 = r1->non_negative();
  if (!(s.minor_radius < s.major_radius)) n.fail("minor_radius must be below major_radius");
  return s;
}

tori::TorusShape parse_shape(const SceneNode& n) {
  n.expect_keys({"major_radius", "minor_radius", "minor_radius_1"});
  tori::TorusShape s;
  s.major_radius = n.at("major_radius").positive();
  s.minor_radius = n.at("minor_radius").positive();
  if (auto r1 = n.find("minor_radius_1")) s.minor_radius_1 = r1->non_negative();
  if (!(s.minor_radius < s.major_radius)) n.fail("minor_radius must be below major_radius");
  return s;
}

// A "torus_segments": [major, minor] resolution (docs/interlocking.md, "Mesh bodies in cells").
std::pair<int, int> parse_torus_segments(const SceneNode& n) {
  const std::vector<int> k = n.integers(3);
  if (k.size() != 2) n.fail("needs [major, minor] segment counts");
  if (k[0] > 256 || k[1] > 256) n.fail("at most 256 segments each way");
  return {k[0], k[1]};
}

// An element of pattern "elements" with a "mesh": {"file": "ring.obj"} (OBJ or OFF, relative to
// the scene file; placed by position and rotation, no radii) or {"torus_segments": [M, m]} (the
// torus of its radii, meshed).
interlocking::CellElement parse_mesh_element(const SceneNode& e) {
  e.expect_keys({"mesh", "major_radius", "minor_radius", "minor_radius_1", "position", "rotation"});
  const SceneNode m = e.at("mesh");
  m.expect_keys({"file", "torus_segments"});
  interlocking::CellElement el;
  if (m.only_key({"file", "torus_segments"}) == "file") {
    for (const char* k : {"major_radius", "minor_radius", "minor_radius_1"})
      if (e.has(k)) e.at(k).fail("a mesh file element has no radii");
    const std::filesystem::path file =
        std::filesystem::path(m.source()).parent_path() / m.at("file").string();
    try {
      el.mesh = interlocking::read_element_mesh(file.string());
    } catch (const std::runtime_error& error) {
      m.at("file").fail(error.what());
    }
  } else {
    el.shape = parse_shape_keys(e);
    const auto [major, minor] = parse_torus_segments(m.at("torus_segments"));
    el.mesh = interlocking::torus_mesh(el.shape, major, minor);
  }
  el.position = e.at("position").vector(3);
  if (auto w = e.find("rotation")) el.rotation = w->vector(3);
  return el;
}

interlocking::RigidCellSpec parse_cell(const SceneNode& n) {
  n.expect_keys({"pattern", "spacing", "node", "link", "link_x", "link_y", "lateral", "elements", "lattice",
                 "supercell", "image_rings", "activation_distance", "anchor", "bending_patch", "mesh"});
  const std::string pattern = n.at("pattern").choice({"chain", "square_rings", "threefold", "elements"});
  interlocking::RigidCellSpec c;
  auto shape_or = [&](const char* key, const char* fallback) {
    if (auto s = n.find(key)) return parse_shape(*s);
    return parse_shape(n.at(fallback));
  };
  if (pattern == "elements") {
    for (const char* k : {"spacing", "node", "link", "link_x", "link_y", "lateral"})
      if (n.has(k)) n.at(k).fail("only for the patterns chain, square_rings, threefold");
    for (const SceneNode& e : n.at("elements").items()) {
      if (e.has("mesh")) {
        if (n.has("mesh")) e.at("mesh").fail("the cell's \"mesh\" already meshes every element");
        c.elements.push_back(parse_mesh_element(e));
        continue;
      }
      e.expect_keys({"major_radius", "minor_radius", "minor_radius_1", "position", "rotation"});
      interlocking::CellElement el;
      el.shape.major_radius = e.at("major_radius").positive();
      el.shape.minor_radius = e.at("minor_radius").positive();
      if (auto r1 = e.find("minor_radius_1")) el.shape.minor_radius_1 = r1->non_negative();
      if (!(el.shape.minor_radius < el.shape.major_radius)) e.fail("minor_radius must be below major_radius");
      el.position = e.at("position").vector(3);
      if (auto w = e.find("rotation")) el.rotation = w->vector(3);
      c.elements.push_back(el);
    }
    if (c.elements.empty()) n.at("elements").fail("needs at least one element");
    const std::vector<SceneNode> rows = n.at("lattice").items();
    if (rows.size() != 2) n.at("lattice").fail("needs two lattice vectors [[x, y], [x, y]]");
    c.lattice.col(0) = rows[0].vector(2);
    c.lattice.col(1) = rows[1].vector(2);
  } else {
    if (n.has("elements") || n.has("lattice")) n.fail("\"elements\" and \"lattice\" need the pattern \"elements\"");
    const double s = n.at("spacing").positive();
    if (pattern == "chain")
      c = interlocking::chain_cell(shape_or("node", "node"), shape_or("link", "node"), s,
                                   n.has("lateral") ? n.at("lateral").positive() : 10.0 * s);
    else if (pattern == "square_rings")
      c = interlocking::square_ring_cell(shape_or("node", "node"), shape_or("link_x", "link"),
                                         shape_or("link_y", "link"), s);
    else
      c = interlocking::threefold_cell(shape_or("node", "node"), shape_or("link", "node"), s);
  }
  if (auto m = n.find("mesh")) {  // every element the meshed torus of its radii
    m->expect_keys({"torus_segments"});
    const auto [major, minor] = parse_torus_segments(m->at("torus_segments"));
    c = interlocking::with_torus_meshes(c, major, minor);
  }
  if (auto k = n.find("image_rings")) c.image_rings = k->integer(1);
  if (auto d = n.find("activation_distance")) c.activation_distance = d->positive();
  if (auto a = n.find("anchor")) c.anchor = a->integer(0);
  if (auto sc = n.find("supercell")) {
    const std::vector<int> counts = sc->integers(1);
    if (counts.size() != 2) sc->fail("needs [nx, ny]");
    c = interlocking::supercell(c, counts[0], counts[1]);
  }
  if (auto bp = n.find("bending_patch")) {
    bp->expect_keys({"radius", "rim_width"});
    try {
      c = interlocking::disc_patch(c, bp->at("radius").positive(), bp->at("rim_width").positive());
    } catch (const std::invalid_argument& e) {
      bp->fail(e.what());
    }
  }
  try {
    interlocking::validate_cell(c);
    const interlocking::PeriodicRigidCell check(c);  // refuses overlapping rest placements
  } catch (const std::invalid_argument& e) {
    n.fail(e.what());
  }
  return c;
}

void parse_limit_options(const SceneNode& n, interlocking::LimitOptions& o) {
  if (auto v = n.find("max_strain")) o.max_strain = v->positive();
  if (auto v = n.find("tolerance")) o.tolerance = v->positive();
  if (auto v = n.find("initial_step")) o.initial_step = v->positive();
  if (auto v = n.find("lock_fraction")) o.lock_fraction = v->open_interval(0.0, 1.0);
}

interlocking::LoadPath make_path(const std::string& loading, double degrees, double shear) {
  const double angle = degrees * M_PI / 180.0;
  interlocking::LoadPath p = loading == "uniaxial" ? interlocking::uniaxial_path(angle)
                                                   : interlocking::principal_path(angle);
  p.offset(0, 1) = p.offset(1, 0) = shear;
  return p;
}

InterlockingDesignSpec parse_design(const SceneNode& n, const interlocking::RigidCellSpec& cell) {
  n.expect_keys({"parameters", "targets", "margin", "reach", "optimizer", "gradcheck"});
  InterlockingDesignSpec d;
  for (const SceneNode& p : n.at("parameters").items()) {
    p.expect_keys({"element", "radius", "lower", "upper"});
    DesignVariable v;
    v.element = p.at("element").integer(0);
    // A patch's variables name elements of the tiling it was cut from (every copy follows).
    try {
      radius_entries(cell, v);
    } catch (const std::invalid_argument&) {
      p.at("element").fail(cell.bending_patch ? "no such element in the patch's tiling" : "no such element");
    }
    v.major = p.at("radius").choice({"major", "minor"}) == "major";
    v.lower = p.at("lower").positive();
    v.upper = p.at("upper").positive();
    if (!(v.lower < v.upper)) p.fail("lower must be below upper");
    d.variables.push_back(v);
  }
  if (d.variables.empty()) n.at("parameters").fail("needs at least one parameter");
  for (const SceneNode& t : n.at("targets").items()) {
    // A patch's limits are curvatures: its targets say "curvature" (a cell's "strain").
    const char* measure = cell.bending_patch ? "curvature" : "strain";
    t.expect_keys({"loading", "angle_degrees", measure});
    const std::string loading = t.has("loading") ? t.at("loading").choice({"principal", "uniaxial"}) : "uniaxial";
    LimitTarget target;
    target.path = make_path(loading, t.at("angle_degrees").number(), 0.0);
    target.strain = t.at(measure).number();
    d.targets.push_back(target);
  }
  if (d.targets.empty()) n.at("targets").fail("needs at least one target");
  if (auto m = n.find("margin")) d.margin = m->non_negative();
  if (auto r = n.find("reach")) d.reach = r->positive();
  d.optimizer.backend = OptimizerBackend::nlopt_mma;
  d.optimizer.max_iterations = 50;
  d.optimizer.gradient_tolerance = 1e-10;
  d.optimizer.checkpoint_every = 0;
  if (auto o = n.find("optimizer")) {
    OptimizerSectionSupport support{"an interlocking design", false, false, {}};
    support.needs.bounds = true;
    support.needs.inequality_constraints = true;
    d.optimizer = parse_optimizer_section(*o, d.optimizer, support);
  }
  d.gradcheck.initial_step = 1e-4;
  if (auto g = n.find("gradcheck")) {
    g->expect_keys({"initial_step", "halvings"});
    if (auto s = g->find("initial_step")) d.gradcheck.initial_step = s->positive();
    if (auto h = g->find("halvings")) d.gradcheck.halvings = h->integer(4);
  }
  return d;
}

}  // namespace

std::vector<interlocking::LoadPath> InterlockingBoundarySpec::paths() const {
  std::vector<interlocking::LoadPath> out;
  // Uniaxial stretch along t and t + 180 degrees is the same path: half a turn suffices.
  const double span = loading == "uniaxial" ? 180.0 : 360.0;
  for (int k = 0; k < directions; ++k) out.push_back(make_path(loading, span * k / directions, shear));
  return out;
}

InterlockingScene parse_interlocking_scene(const SceneNode& root) {
  root.expect_keys({"name", "description", "interlocking"});
  const SceneNode n = root.at("interlocking");
  n.expect_keys({"cell", "boundary", "design"});
  InterlockingScene scene;
  scene.cell = parse_cell(n.at("cell"));
  if (auto b = n.find("boundary")) {
    b->expect_keys({"loading", "directions", "shear", "vtu", "max_strain", "tolerance", "initial_step",
                    "lock_fraction", "single_curvature"});
    if (auto l = b->find("loading")) scene.boundary.loading = l->choice({"principal", "uniaxial"});
    if (auto d = b->find("directions")) scene.boundary.directions = d->integer(1);
    if (auto s = b->find("shear")) scene.boundary.shear = s->number();
    if (auto v = b->find("vtu")) scene.boundary.vtu = v->boolean();
    parse_limit_options(*b, scene.boundary.options);
    if (auto c = b->find("single_curvature")) {
      scene.boundary.single_curvature = c->boolean();
      if (scene.boundary.single_curvature) {
        if (scene.cell.bending_patch) c->fail("needs a periodic cell (not cell.bending_patch)");
        if (scene.boundary.loading != "uniaxial") c->fail("needs \"loading\": \"uniaxial\" (the curvature's direction)");
        if (scene.boundary.shear != 0.0) c->fail("does not take a shear");
        if (n.find("design")) c->fail("has no limit design (remove \"design\" or single_curvature)");
        if (interlocking::is_mesh_cell(scene.cell))
          c->fail("needs implicit tori (the curved cell's contact has no mesh bodies)");
      }
    }
  }
  if (auto d = n.find("design")) {
    if (interlocking::is_mesh_cell(scene.cell))
      d->fail("limit design needs implicit tori (mesh cells have no limit derivatives)");
    scene.design = parse_design(*d, scene.cell);
  }
  return scene;
}

}  // namespace tailor
