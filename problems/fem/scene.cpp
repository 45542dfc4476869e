#include "problems/fem/scene.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <system_error>

#include "problems/fem/dynamic_scene.hpp"
#include "problems/fem/linear_solver_choice.hpp"
#include "problems/fem/scene_parsing.hpp"
#include "problems/fem/spline_curves_json.hpp"
#include "problems/json_duplicate_keys.hpp"
#include "problems/solver_keys.hpp"

namespace tailor {
namespace {

namespace fs = std::filesystem;

void parse_bounds(const SceneNode& node, int size, Eigen::VectorXd& min, Eigen::VectorXd& max) {
  min = node.at("min").vector(size);
  max = node.at("max").vector(static_cast<int>(min.size()));
  for (Eigen::Index k = 0; k < min.size(); ++k)
    if (!(max[k] >= min[k])) node.at("max").fail("every entry must be >= the matching entry of min");
}

}  // namespace

std::string resolve_scene_path(const std::string& directory, const std::string& path) {
  const fs::path p(path);
  if (p.is_absolute() || directory.empty()) return p.lexically_normal().string();
  return (fs::path(directory) / p).lexically_normal().string();
}

std::vector<DataLine> read_data_file(const SceneNode& node, const std::string& path) {
  std::ifstream in(path);
  if (!in) node.fail("cannot open file '" + path + "'");
  std::vector<DataLine> lines;
  std::string text;
  for (int number = 1; std::getline(in, text); ++number) {
    if (const auto hash = text.find('#'); hash != std::string::npos) text.erase(hash);
    std::istringstream words(text);
    DataLine line{number, {}};
    for (std::string w; words >> w;) line.tokens.push_back(w);
    if (!line.tokens.empty()) lines.push_back(std::move(line));
  }
  return lines;
}

std::optional<double> parse_number(const std::string& token) {
  char* end = nullptr;
  const double v = std::strtod(token.c_str(), &end);
  if (end != token.c_str() + token.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<int> parse_vertex_id(const std::string& token) {
  const auto v = parse_number(token);
  if (!v || *v < 0 || *v != std::floor(*v) || *v > std::numeric_limits<int>::max()) return std::nullopt;
  return static_cast<int>(*v);
}

std::vector<double> read_positive_values(const SceneNode& node, const std::string& directory) {
  const std::string path = resolve_scene_path(directory, node.string());
  std::vector<double> values;
  for (const DataLine& line : read_data_file(node, path))
    for (const std::string& token : line.tokens) {
      const auto v = parse_number(token);
      if (!v || !(*v > 0.0))
        node.fail("'" + path + "' line " + std::to_string(line.line) + ": expected a number > 0, got '" +
                  token + "'");
      values.push_back(*v);
    }
  if (values.empty()) node.fail("'" + path + "' holds no values");
  return values;
}

VertexSelector parse_vertex_selector(const SceneNode& node, const std::string& directory) {
  VertexSelector s;
  s.key = node.path();
  const std::string kind = node.only_key({"plane", "box", "list", "file", "boundary"});
  const SceneNode body = node.at(kind.c_str());
  if (kind == "boundary") {
    if (!body.boolean()) body.fail("expected true (every vertex of a boundary facet)");
    s.kind = VertexSelector::Kind::boundary;
    return s;
  }
  if (kind == "plane") {
    body.expect_keys({"axis", "value", "tolerance"});
    s.kind = VertexSelector::Kind::plane;
    const std::string axis = body.at("axis").choice({"x", "y", "z"});
    s.axis = axis[0] - 'x';
    s.value = body.at("value").number();
    if (auto t = body.find("tolerance")) s.tolerance = t->positive();
  } else if (kind == "box") {
    body.expect_keys({"min", "max", "tolerance"});
    s.kind = VertexSelector::Kind::box;
    parse_bounds(body, -1, s.min, s.max);
    if (auto t = body.find("tolerance")) s.tolerance = t->positive();
  } else if (kind == "list") {
    s.ids = body.integers(0);
    if (s.ids.empty()) body.fail("selects no vertices (the list is empty)");
  } else {
    const std::string path = resolve_scene_path(directory, body.string());
    for (const DataLine& line : read_data_file(body, path))
      for (const std::string& token : line.tokens) {
        const auto id = parse_vertex_id(token);
        if (!id)
          body.fail("'" + path + "' line " + std::to_string(line.line) +
                    ": expected a vertex id (integer >= 0), got '" + token + "'");
        s.ids.push_back(*id);
      }
    if (s.ids.empty()) body.fail("selects no vertices ('" + path + "' lists none)");
  }
  return s;
}

namespace {

// Installed memory (0 when unknown).
double physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page_size > 0 ? static_cast<double>(pages) * static_cast<double>(page_size) : 0.0;
}

}  // namespace

void check_mesh_fits(const SceneNode& node, double elements, int dim) {
  // The elements' count must fit int indices, and the model alone (element data and the
  // Hessian pattern, ~3 KiB per tet, ~1 KiB per triangle) must fit in this machine's memory,
  // before any factorization.
  const double bytes = elements * (dim == 3 ? 3072.0 : 1024.0);
  const double memory = physical_memory_bytes();
  constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
  if (elements > 2e9 || (memory > 0 && bytes > memory)) {
    std::ostringstream what;
    what << std::setprecision(3) << elements << (dim == 3 ? " tets" : " triangles") << " would need at least "
         << bytes / kGiB << " GiB for the model alone";
    if (memory > 0) what << ", more than this machine's " << memory / kGiB << " GiB";
    if (elements > 2e9) what << ", and more elements than int indices can count";
    node.fail(what.str() + ": use fewer cells");
  }
}

namespace {

ElementSelector parse_element_selector(const SceneNode& node) {
  ElementSelector s;
  s.key = node.path();
  if (node.is_string()) {
    node.choice({"all"});
    s.kind = ElementSelector::Kind::all;
    return s;
  }
  if (node.only_key({"region", "box"}) == "region") {
    s.kind = ElementSelector::Kind::region;
    s.region = node.at("region").integer(0);
  } else {
    s.kind = ElementSelector::Kind::box;
    const SceneNode box = node.at("box");
    box.expect_keys({"min", "max"});
    parse_bounds(box, -1, s.min, s.max);
  }
  return s;
}

MeshSpec parse_mesh(const SceneNode& node, const std::string& directory) {
  MeshSpec m;
  node.expect_keys({"file", "box", "rectangle", "order"});
  int shapes = 0;
  std::string kind;
  for (const char* k : {"file", "box", "rectangle"})
    if (node.has(k)) {
      ++shapes;
      kind = k;
    }
  if (shapes != 1) node.fail("expected exactly one of the keys \"file\", \"box\", \"rectangle\" (and optionally \"order\")");
  if (auto order = node.find("order")) {
    m.order = order->integer(1);
    if (m.order > 2) order->fail("expected 1 (linear elements) or 2 (quadratic elements), got " + std::to_string(m.order));
  }
  if (kind == "file") {
    m.kind = MeshSpec::Kind::file;
    m.file = resolve_scene_path(directory, node.at("file").string());
    return m;
  }
  const int dim = kind == "box" ? 3 : 2;
  m.kind = kind == "box" ? MeshSpec::Kind::box : MeshSpec::Kind::rectangle;
  const SceneNode body = node.at(kind.c_str());
  body.expect_keys({"min", "max", "cells"});
  parse_bounds(body, dim, m.min, m.max);
  for (int k = 0; k < dim; ++k)
    if (!(m.max[k] > m.min[k])) body.at("max").fail("every entry must be > the matching entry of min");
  const SceneNode cells = body.at("cells");
  const std::vector<int> counts = cells.integers(1);
  if (static_cast<int>(counts.size()) != dim)
    cells.fail("expected " + std::to_string(dim) + " cell counts, got " + std::to_string(counts.size()));
  m.cells = Eigen::Map<const Eigen::VectorXi>(counts.data(), dim);
  double elements = dim == 3 ? 6.0 : 2.0;
  for (int k = 0; k < dim; ++k) elements *= counts[static_cast<std::size_t>(k)];
  check_mesh_fits(cells, elements, dim);
  return m;
}

// "model": "spline" (docs/materials.md, "Spline materials in scenes"): exactly one of "preset" (with
// youngs_modulus and poisson_ratio) and "curves" (inline or {"file": ...}, the moduli then
// come from the curves).
void parse_spline_material(const SceneNode& node, const std::string& directory, MaterialSpec& m) {
  if (node.has("preset") == node.has("curves"))
    node.fail(
        "a spline material needs exactly one of \"preset\" (with youngs_modulus and poisson_ratio) and "
        "\"curves\"");
  if (node.has("youngs_modulus_file"))
    node.at("youngs_modulus_file").fail("not supported by spline materials (their stiffness is the curves)");
  if (auto preset = node.find("preset")) {
    m.youngs_modulus = node.at("youngs_modulus").positive();
    m.poisson_ratio = node.at("poisson_ratio").open_interval(-1.0, 0.5);
    m.spline_curves = std::make_shared<const PrincipalStretchCurves>(
        principal_stretch_preset(parse_spline_preset(preset->choice({"corotated", "stvk", "neo_hookean"})),
                                 lame_from_young_poisson(m.youngs_modulus, m.poisson_ratio)));
    return;
  }
  for (const char* key : {"youngs_modulus", "poisson_ratio"})
    if (node.has(key))
      node.at(key).fail(
          "not used with explicit curves (the curves carry the stiffness; use \"preset\" to "
          "build curves from E and nu)");
  const SceneNode curves = node.at("curves");
  m.spline_curves = std::make_shared<const PrincipalStretchCurves>(parse_curves_or_file(curves, directory));
  const LameParameters lame = small_strain_lame(*m.spline_curves);
  // Stable at rest: shear modulus > 0 and bulk modulus lambda + 2 mu / 3 > 0.
  if (!(lame.mu > 0.0) || !(lame.lambda + 2.0 * lame.mu / 3.0 > 0.0))
    curves.fail("the curves are not stable at rest: small-strain Lame parameters lambda = " +
                std::to_string(lame.lambda) + ", mu = " + std::to_string(lame.mu) +
                " (need mu > 0 and lambda + 2 mu / 3 > 0)");
  m.youngs_modulus = lame.mu * (3.0 * lame.lambda + 2.0 * lame.mu) / (lame.lambda + lame.mu);
  m.poisson_ratio = lame.lambda / (2.0 * (lame.lambda + lame.mu));
}

MaterialSpec parse_material(const SceneNode& node, const std::string& directory) {
  node.expect_keys({"elements", "model", "youngs_modulus", "youngs_modulus_file", "poisson_ratio", "density",
                    "preset", "curves"});
  MaterialSpec m;
  m.key = node.path();
  m.elements = parse_element_selector(node.at("elements"));
  std::vector<std::string> models = material_names();
  models.emplace_back("spline");  // principal-stretch curves, parsed below
  const std::string model = node.at("model").choice(models);
  if (auto d = node.find("density")) m.density = d->non_negative();
  if (model == "spline") {
    parse_spline_material(node, directory, m);
    return m;
  }
  for (const char* key : {"preset", "curves"})
    if (node.has(key)) node.at(key).fail("only used by \"model\": \"spline\"");
  m.model = parse_material_kind(model);
  if (node.has("youngs_modulus") == node.has("youngs_modulus_file"))
    node.fail(
        "give exactly one of \"youngs_modulus\" (a number) and \"youngs_modulus_file\" (one value per "
        "element)");
  if (auto e = node.find("youngs_modulus")) {
    m.youngs_modulus = e->positive();
  } else {
    m.youngs_modulus_values = read_positive_values(node.at("youngs_modulus_file"), directory);
  }
  m.poisson_ratio = node.at("poisson_ratio").open_interval(-1.0, 0.5);
  return m;
}

DirichletSpec parse_dirichlet(const SceneNode& node, const std::string& directory) {
  node.expect_keys({"vertices", "displacement", "components"});
  DirichletSpec d;
  d.key = node.path();
  d.vertices = parse_vertex_selector(node.at("vertices"), directory);
  if (auto u = node.find("displacement")) d.displacement = u->vector();
  if (auto c = node.find("components")) {
    d.components = c->integers(0);
    if (d.components.empty()) c->fail("expected at least one component");
    for (std::size_t i = 0; i < d.components.size(); ++i) {
      if (d.components[i] > 2)
        c->items()[i].fail("expected a component 0, 1 or 2, got " + std::to_string(d.components[i]));
      for (std::size_t j = 0; j < i; ++j)
        if (d.components[j] == d.components[i]) c->items()[i].fail("component listed twice");
    }
  }
  return d;
}

NodalForceFile parse_nodal_file(const SceneNode& node, const std::string& directory) {
  NodalForceFile f;
  f.key = node.path();
  const std::string path = resolve_scene_path(directory, node.string());
  const std::vector<DataLine> lines = read_data_file(node, path);
  if (lines.empty()) node.fail("'" + path + "' holds no forces");
  const std::size_t columns = lines.front().tokens.size();
  // Sized only by a valid column count (the loop refuses any other on line 1): a long first line
  // must not make this lines x columns.
  const bool valid_columns = columns == 3 || columns == 4;
  f.forces.resize(static_cast<Eigen::Index>(lines.size()),
                  valid_columns ? static_cast<Eigen::Index>(columns) - 1 : 0);
  for (std::size_t r = 0; r < lines.size(); ++r) {
    const DataLine& line = lines[r];
    const std::string where = "'" + path + "' line " + std::to_string(line.line) + ": ";
    if ((columns != 3 && columns != 4) || line.tokens.size() != columns)
      node.fail(where + "expected 'vertex fx fy' or 'vertex fx fy fz' on every line, got " +
                std::to_string(line.tokens.size()) + " values");
    const auto id = parse_vertex_id(line.tokens[0]);
    if (!id) node.fail(where + "expected a vertex id (integer >= 0), got '" + line.tokens[0] + "'");
    f.vertices.push_back(*id);
    for (std::size_t k = 1; k < columns; ++k) {
      const auto v = parse_number(line.tokens[k]);
      if (!v) node.fail(where + "expected a number, got '" + line.tokens[k] + "'");
      f.forces(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(k) - 1) = *v;
    }
  }
  return f;
}

LoadSpec parse_loads(const SceneNode& node, const std::string& directory) {
  node.expect_keys({"gravity", "tractions", "nodal", "nodal_file"});
  LoadSpec loads;
  if (auto g = node.find("gravity")) {
    loads.gravity = g->vector();
    loads.gravity_key = g->path();
  }
  if (auto list = node.find("tractions"))
    for (const SceneNode& item : list->items()) {
      item.expect_keys({"faces", "traction"});
      loads.tractions.push_back(
          {parse_vertex_selector(item.at("faces"), directory), item.at("traction").vector(), item.path()});
    }
  if (auto list = node.find("nodal"))
    for (const SceneNode& item : list->items()) {
      item.expect_keys({"vertices", "force"});
      loads.nodal.push_back(
          {parse_vertex_selector(item.at("vertices"), directory), item.at("force").vector(), item.path()});
    }
  if (auto file = node.find("nodal_file")) loads.nodal_file = parse_nodal_file(*file, directory);
  return loads;
}

SolverSpec parse_solver(const SceneNode& node) {
  node.expect_keys({"max_iterations", "relative_tolerance", "absolute_tolerance", "hessian", "load_steps",
                    "reuse_factorization", "threads", "linear_solver", "petsc_options"});
  SolverSpec s;
  if (auto v = node.find("linear_solver")) s.linear_solver = v->choice({"cholmod", "petsc"});
  if (auto v = node.find("petsc_options")) {
    if (s.linear_solver != "petsc") v->fail("needs \"linear_solver\": \"petsc\"");
    if (!v->is_string()) v->fail("expected a string of PETSc options, e.g. \"-ksp_type cg -pc_type gamg\"");
  }
  if (s.linear_solver != "cholmod") {
    const auto options = node.find("petsc_options");
    try {
      s.newton.linear_solver =
          make_linear_solver({s.linear_solver, options ? options->string() : std::string()});
    } catch (const std::invalid_argument& e) {
      (options ? *options : node.at("linear_solver")).fail(e.what());
    }
  }
  if (auto v = node.find("max_iterations")) s.newton.max_iterations = v->integer(1);
  if (auto v = node.find("relative_tolerance")) s.newton.relative_tolerance = v->open_interval(0.0, 1.0);
  if (auto v = node.find("absolute_tolerance")) s.newton.absolute_tolerance = v->non_negative();
  if (auto v = node.find("hessian")) {
    const std::string choice = v->choice({"adaptive", "exact", "projected"});
    s.newton.hessian = choice == "exact"       ? NewtonHessian::exact
                       : choice == "projected" ? NewtonHessian::projected
                                               : NewtonHessian::adaptive;
  }
  if (auto v = node.find("load_steps")) s.load_steps = v->integer(1);
  if (auto v = node.find("reuse_factorization")) s.newton.reuse_factorization = parse_factor_reuse(*v);
  if (auto threads = node.find("threads")) {
    threads->expect_keys({"assembly", "blas", "factorization"});
    ThreadSettings t;
    if (auto v = threads->find("assembly")) t.assembly = v->integer(0);
    if (auto v = threads->find("blas")) t.blas = v->integer(0);
    if (auto v = threads->find("factorization")) {
      t.factorization = v->integer(0);
      if (t.factorization > 1)
        v->fail("expected 1 (CHOLMOD's OpenMP loops serialized) or 0 (as CHOLMOD was built)");
    }
    s.threads = t;
  }
  return s;
}

}  // namespace

std::string axis_name(int axis) { return std::string(1, static_cast<char>('x' + axis)); }

nlohmann::json parse_scene_document(const std::string& json_text, const std::string& source) {
  // The last object key read, to say where a number that overflows double stands (nlohmann
  // reports that without a position).
  std::string last_key;
  const auto track_keys = [&last_key](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    if (event == nlohmann::json::parse_event_t::key) last_key = parsed.get<std::string>();
    return true;
  };
  try {
    nlohmann::json document = nlohmann::json::parse(json_text, track_keys);
    if (const auto duplicate = find_duplicate_key(json_text))
      throw SceneError(source + ": " + duplicate->path + ": the key appears twice (line " +
                       std::to_string(duplicate->first_line) + ", column " + std::to_string(duplicate->first_column) +
                       " and line " + std::to_string(duplicate->line) + ", column " +
                       std::to_string(duplicate->column) + "); JSON would keep only the last value");
    return document;
  } catch (const nlohmann::json::parse_error& e) {
    // e.what() reads "[json.exception.parse_error.101] parse error at line L, column C: ...".
    std::string what = e.what();
    if (const auto bracket = what.find("] "); what.rfind("[json.", 0) == 0 && bracket != std::string::npos)
      what.erase(0, bracket + 2);
    throw SceneError(source + ": invalid JSON (byte " + std::to_string(e.byte) + "): " + what);
  } catch (const nlohmann::json::exception& e) {
    // out_of_range.406: a number beyond the range of double (e.g. 1e400).
    throw SceneError(source + ": invalid JSON: a number is out of the range of double precision" +
                     (last_key.empty() ? std::string() : " (at or after key \"" + last_key + "\")") +
                     "; numbers must be finite and below about 1.8e308");
  }
}

namespace {

std::string read_scene_text(const std::string& path) {
  std::error_code error;
  if (fs::is_directory(path, error)) throw SceneError(path + ": is a folder, not a scene file");
  std::ifstream in(path);
  if (!in) throw SceneError(path + ": cannot open the scene file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

nlohmann::json read_scene_document(const std::string& path) {
  return parse_scene_document(read_scene_text(path), path);
}

Scene parse_scene(const std::string& json_text, const std::string& source, const std::string& directory) {
  const nlohmann::json document = parse_scene_document(json_text, source);
  return parse_scene(SceneNode(document, source, ""), directory);
}

Scene parse_scene(const SceneNode& root, const std::string& directory) {
  Scene scene;
  scene.source = root.source();
  scene.directory = directory;
  root.expect_keys(
      {"name", "description", "mesh", "materials", "dirichlet", "loads", "solver", "inverse", "dynamics"});
  if (auto n = root.find("name")) {
    scene.name = n->string();
    if (scene.name.empty()) n->fail("expected a non-empty string");
  }
  if (auto d = root.find("description")) d->string();
  scene.mesh = parse_mesh(root.at("mesh"), directory);
  const SceneNode materials = root.at("materials");
  for (const SceneNode& item : materials.items()) scene.materials.push_back(parse_material(item, directory));
  if (scene.materials.empty()) materials.fail("expected at least one material");
  if (auto list = root.find("dirichlet"))
    for (const SceneNode& item : list->items()) scene.dirichlet.push_back(parse_dirichlet(item, directory));
  if (auto loads = root.find("loads")) scene.loads = parse_loads(*loads, directory);
  if (auto solver = root.find("solver")) scene.solver = parse_solver(*solver);
  if (auto inverse = root.find("inverse"))
    scene.inverse = std::make_shared<const InverseSpec>(parse_inverse_section(*inverse, directory));
  if (auto dynamics = root.find("dynamics"))
    scene.dynamics = std::make_shared<const DynamicsSpec>(parse_dynamics_section(*dynamics, directory));
  return scene;
}

Scene read_scene(const std::string& path) {
  const fs::path file(path);
  Scene scene = parse_scene(read_scene_text(path), path, file.parent_path().string());
  if (scene.name.empty()) scene.name = file.stem().string();
  return scene;
}

}  // namespace tailor
