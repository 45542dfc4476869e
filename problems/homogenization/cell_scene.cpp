#include "problems/homogenization/cell_scene.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "forward/homogenization/cell_mesh.hpp"
#include "forward/mesh/mesh_io.hpp"
#include "problems/fem/scene.hpp"
#include "problems/fem/scene_parsing.hpp"
#include "problems/scene_node.hpp"

namespace tailor {
namespace {

Eigen::MatrixXd parse_lattice(const SceneNode& node) {
  const std::vector<SceneNode> rows = node.items();
  const int dim = static_cast<int>(rows.size());
  if (dim != 2 && dim != 3) node.fail("expected 2 or 3 lattice vectors");
  Eigen::MatrixXd A(dim, dim);
  for (int k = 0; k < dim; ++k) A.col(k) = rows[k].vector(dim);
  if (!(A.determinant() > 0.0))
    node.fail("the lattice vectors must be right-handed and independent (det > 0)");
  return A;
}

Eigen::VectorXd centroid(const Mesh& mesh, int e) {
  Eigen::VectorXd c = Eigen::VectorXd::Zero(mesh.dim());
  for (int a = 0; a <= mesh.dim(); ++a) c += mesh.rest_positions.row(mesh.elements(e, a)).transpose();
  return c / (mesh.dim() + 1);
}

void apply_phase_rule(const SceneNode& rule, const PeriodicCell& cell, int num_phases,
                      std::vector<int>& phase) {
  rule.expect_keys({"phase", "disc", "sphere", "slab"});
  const int target = rule.at("phase").integer(0);
  if (target >= num_phases)
    rule.at("phase").fail("no such material (there are " + std::to_string(num_phases) + ")");
  const int shapes = rule.has("disc") + rule.has("sphere") + rule.has("slab");
  if (shapes != 1) rule.fail("give exactly one of \"disc\", \"sphere\" and \"slab\"");
  const std::string shape = rule.has("disc") ? "disc" : (rule.has("sphere") ? "sphere" : "slab");
  const SceneNode spec = rule.at(shape.c_str());
  const int dim = cell.dim();
  const Eigen::MatrixXd inverse = cell.lattice.inverse();
  const Mesh& mesh = cell.mesh;
  if (shape == "slab") {
    spec.expect_keys({"axis", "from", "to"});
    const int axis = spec.at("axis").integer(0);
    if (axis >= dim) spec.at("axis").fail("must be below the dimension");
    const double from = spec.at("from").number(), to = spec.at("to").number();
    if (!(from < to)) spec.fail("need from < to");
    for (int e = 0; e < mesh.num_elements(); ++e) {
      const double f = (inverse * (centroid(mesh, e) - cell.origin))[axis];
      if (f >= from && f < to) phase[e] = target;
    }
    return;
  }
  if ((shape == "disc") != (dim == 2)) spec.fail("use \"disc\" in 2D and \"sphere\" in 3D");
  spec.expect_keys({"center", "radius"});
  const Eigen::VectorXd center = spec.at("center").vector(dim);
  const double radius = spec.at("radius").positive();
  for (int e = 0; e < mesh.num_elements(); ++e) {
    Eigen::VectorXd df = inverse * (centroid(mesh, e) - center);
    for (int k = 0; k < dim; ++k) df[k] -= std::round(df[k]);
    // The nearest image among the neighbours of the rounded one (skewed lattices).
    double best = 1e300;
    const int neighbours = dim == 2 ? 9 : 27;
    for (int c = 0; c < neighbours; ++c) {
      Eigen::VectorXd shift(dim);
      int code = c;
      for (int k = 0; k < dim; ++k, code /= 3) shift[k] = code % 3 - 1;
      best = std::min(best, (cell.lattice * (df + shift)).norm());
    }
    if (best < radius) phase[e] = target;
  }
}

}  // namespace

Vector CellScene::youngs_modulus() const {
  Vector E(element_phase.size());
  for (std::size_t e = 0; e < element_phase.size(); ++e) E[e] = materials[element_phase[e]].youngs_modulus;
  return E;
}

Vector CellScene::poisson_ratio() const {
  Vector nu(element_phase.size());
  for (std::size_t e = 0; e < element_phase.size(); ++e) nu[e] = materials[element_phase[e]].poisson_ratio;
  return nu;
}

CellScene parse_cell_scene(const SceneNode& root, const std::string& directory) {
  root.expect_keys({"type", "name", "description", "cell", "plane", "materials", "phases", "directions",
                    "design", "stress_strain", "rod_network"});
  if (root.at("type").string() != "periodic_cell") root.at("type").fail("expected \"periodic_cell\"");
  CellScene scene;
  scene.source = root.source();
  if (const auto name = root.find("name")) scene.name = name->string();
  if (const auto rods = root.find("rod_network")) {
    for (const char* key : {"cell", "materials", "phases", "plane", "stress_strain", "design"})
      if (root.has(key)) root.at(key).fail("does not apply to a \"rod_network\" cell");
    scene.rod_network = parse_rod_network_scene(*rods);
    if (const auto directions = root.find("directions")) scene.directions = directions->integer(4);
    return scene;
  }
  const SceneNode cell = root.at("cell");
  cell.expect_keys({"lattice", "origin", "grid", "split", "mesh", "tolerance", "periodic"});
  const Eigen::MatrixXd A = parse_lattice(cell.at("lattice"));
  const int dim = static_cast<int>(A.rows());
  const Eigen::VectorXd origin =
      cell.has("origin") ? cell.at("origin").vector(dim) : Eigen::VectorXd::Zero(dim);
  const double tolerance = cell.has("tolerance") ? cell.at("tolerance").open_interval(0.0, 0.1) : 1e-8;
  Mesh mesh;
  if (cell.has("grid") == cell.has("mesh")) cell.fail("give exactly one of \"grid\" and \"mesh\"");
  if (cell.has("grid")) {
    const std::vector<int> grid = cell.at("grid").integers(1);
    if (static_cast<int>(grid.size()) != dim)
      cell.at("grid").fail("expected " + std::to_string(dim) + " counts");
    if (dim == 2) {
      const TriangleSplit split =
          cell.has("split")
              ? parse_triangle_split(cell.at("split").choice({"forward", "backward", "crossed"}))
              : TriangleSplit::forward;
      check_mesh_fits(cell.at("grid"), (split == TriangleSplit::crossed ? 4.0 : 2.0) * grid[0] * grid[1], 2);
      mesh = lattice_triangle_mesh(A, origin, grid[0], grid[1], split);
    } else {
      if (cell.has("split")) cell.at("split").fail("\"split\" applies to 2D cells only");
      check_mesh_fits(cell.at("grid"), 6.0 * grid[0] * grid[1] * grid[2], 3);
      mesh = lattice_tet_mesh(A, origin, grid[0], grid[1], grid[2]);
    }
  } else {
    mesh = read_mesh(resolve_scene_path(directory, cell.at("mesh").string()));
    if (mesh.dim() != dim)
      cell.at("mesh").fail("the mesh is " + std::to_string(mesh.dim()) + "D but the lattice " +
                           std::to_string(dim) + "D");
  }
  try {
    std::vector<bool> periodic(dim, true);
    if (cell.has("periodic")) {
      const std::vector<SceneNode> flags = cell.at("periodic").items();
      if (static_cast<int>(flags.size()) != dim) cell.at("periodic").fail("need one flag per lattice vector");
      for (int k = 0; k < dim; ++k) periodic[k] = flags[k].boolean();
      if (periodic != std::vector<bool>(dim, true) && periodic != std::vector<bool>{true, true, false})
        cell.at("periodic").fail("either all periodic, or [true, true, false] (a plate-like 3D cell)");
    }
    scene.cell = make_periodic_cell(mesh, A, origin, tolerance, periodic);
  } catch (const PeriodicityError& e) {
    cell.fail(e.what());
  }
  if (const auto plane = root.find("plane")) {
    if (dim != 2) plane->fail("\"plane\" applies to 2D cells only");
    scene.plane =
        plane->choice({"strain", "stress"}) == "stress" ? PlaneMode::plane_stress : PlaneMode::plane_strain;
  }
  // Materials by index (element region r takes materials[r]) or by the mesh file's tags
  // ({"region": 1, ...}: every entry names one, and elements take the entry of their tag).
  std::vector<int> region_tags;
  const std::vector<SceneNode> material_nodes = root.at("materials").items();
  for (const SceneNode& m : material_nodes) {
    m.expect_keys({"youngs_modulus", "poisson_ratio", "name", "region"});
    scene.materials.push_back(
        {m.at("youngs_modulus").positive(), m.at("poisson_ratio").open_interval(-1.0, 0.5)});
    if (m.has("region") != material_nodes.front().has("region"))
      m.fail("either every material names its \"region\" or none does");
    if (m.has("region")) {
      const int tag = m.at("region").integer(0);
      for (std::size_t k = 0; k < region_tags.size(); ++k)
        if (region_tags[k] == tag)
          m.at("region").fail("region " + std::to_string(tag) + " is already materials[" + std::to_string(k) +
                              "]");
      region_tags.push_back(tag);
    }
  }
  if (scene.materials.empty()) root.at("materials").fail("need at least one material");
  const int num_phases = static_cast<int>(scene.materials.size());
  const Eigen::VectorXi& element_regions = scene.cell.mesh.element_regions;
  if (!region_tags.empty() && element_regions.size() == 0)
    root.at("materials").fail("materials name regions, but the mesh has none (a generated grid has none)");
  scene.element_phase.assign(scene.cell.mesh.num_elements(), 0);
  for (int e = 0; e < scene.cell.mesh.num_elements(); ++e) {
    const int region = element_regions.size() == 0 ? 0 : element_regions[e];
    if (!region_tags.empty()) {
      const auto found = std::find(region_tags.begin(), region_tags.end(), region);
      if (found == region_tags.end())
        root.at("materials")
            .fail("element " + std::to_string(e) + " has region " + std::to_string(region) +
                  ", which no material names");
      scene.element_phase[e] = static_cast<int>(found - region_tags.begin());
      continue;
    }
    if (region < 0 || region >= num_phases)
      cell.fail("element " + std::to_string(e) + " has region " + std::to_string(region) + " but there are " +
                std::to_string(num_phases) +
                " materials (regions index the materials; or give each material its \"region\")");
    scene.element_phase[e] = region;
  }
  if (const auto phases = root.find("phases"))
    for (const SceneNode& rule : phases->items())
      apply_phase_rule(rule, scene.cell, num_phases, scene.element_phase);
  if (const auto directions = root.find("directions")) scene.directions = directions->integer(4);
  scene.has_design = root.has("design");
  if (const auto curves = root.find("stress_strain")) {
    curves->expect_keys({"material", "max_strain", "steps", "directions"});
    StressStrainSpec spec;
    if (curves->has("material"))
      spec.material = parse_material_kind(curves->at("material").choice(material_names()));
    if (curves->has("max_strain")) spec.max_strain = curves->at("max_strain").open_interval(-0.9, 10.0);
    if (curves->has("steps")) spec.steps = curves->at("steps").integer(1);
    for (const SceneNode& d : curves->at("directions").items()) {
      const Eigen::VectorXd v = d.vector(dim);
      if (!(v.norm() > 0.0)) d.fail("a direction must be nonzero");
      spec.directions.push_back(v.normalized());
    }
    if (spec.directions.empty()) curves->at("directions").fail("need at least one direction");
    if (scene.plane == PlaneMode::plane_stress) curves->fail("nonlinear curves are plane strain only in 2D");
    scene.stress_strain = spec;
  }
  return scene;
}

}  // namespace tailor
