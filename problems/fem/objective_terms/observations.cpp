// "observations": measured displacements of some vertices, read from a text file with one
// "vertex ux uy" (2D) or "vertex ux uy uz" (3D) per line ('#' starts a comment).
#include <map>

#include "problems/fem/inverse_problem.hpp"
#include "problems/fem/objective_terms/builtin_terms.hpp"
#include "problems/fem/scene_parsing.hpp"
#include "problems/fem/scene_selection.hpp"

namespace tailor {
namespace {

std::shared_ptr<ObservationsTerm> read_observations(const SceneNode& node, const std::string& directory) {
  auto t = std::make_shared<ObservationsTerm>();
  t->file = resolve_scene_path(directory, node.string());
  const std::vector<DataLine> lines = read_data_file(node, t->file);
  if (lines.empty()) node.fail("'" + t->file + "' holds no observations");
  const std::size_t columns = lines.front().tokens.size();
  // Sized only by a valid column count (the loop refuses any other on line 1): a long first line
  // must not make this lines x columns.
  const bool valid_columns = columns == 3 || columns == 4;
  t->displacements.resize(static_cast<Eigen::Index>(lines.size()),
                          valid_columns ? static_cast<Eigen::Index>(columns) - 1 : 0);
  std::map<int, int> first_line;  // vertex id -> the line it was first observed on
  for (std::size_t r = 0; r < lines.size(); ++r) {
    const DataLine& line = lines[r];
    const std::string where = "'" + t->file + "' line " + std::to_string(line.line) + ": ";
    if (!valid_columns || line.tokens.size() != columns)
      node.fail(where + "expected 'vertex ux uy' or 'vertex ux uy uz' on every line, got " +
                std::to_string(line.tokens.size()) + " values");
    const auto id = parse_vertex_id(line.tokens[0]);
    if (!id) node.fail(where + "expected a vertex id (integer >= 0), got '" + line.tokens[0] + "'");
    if (const auto [it, fresh] = first_line.emplace(*id, line.line); !fresh)
      node.fail(where + "vertex " + std::to_string(*id) + " is observed twice (also on line " +
                std::to_string(it->second) + ")");
    t->vertices.push_back(*id);
    for (std::size_t k = 1; k < columns; ++k) {
      const auto v = parse_number(line.tokens[k]);
      if (!v) node.fail(where + "expected a number, got '" + line.tokens[k] + "'");
      t->displacements(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(k) - 1) = *v;
    }
  }
  return t;
}

}  // namespace

ObjectiveTermType observations_objective_term() {
  ObjectiveTermType t;
  t.type = "observations";
  t.is_data = true;
  t.keys = t.required = {"file"};
  t.parse = [](const SceneNode& node, const std::string& directory) {
    return read_observations(node.at("file"), directory);
  };
  t.build = [](const ObjectiveTermContext& c) {
    const auto& s = c.settings<ObservationsTerm>();
    const Mesh& mesh = c.problem.setup.mesh;
    const std::string key = c.node.path() + ".file";
    if (s.displacements.cols() != mesh.dim())
      throw_scene_error(c.scene, key,
                        "'" + s.file + "': expected " + std::to_string(mesh.dim()) +
                            " displacement components per line (the mesh is " + std::to_string(mesh.dim()) +
                            "D), got " + std::to_string(s.displacements.cols()));
    for (int v : s.vertices)
      if (v >= mesh.num_vertices())
        throw_scene_error(c.scene, key,
                          "'" + s.file + "': vertex " + std::to_string(v) + " does not exist (the mesh has " +
                              std::to_string(mesh.num_vertices()) + " vertices)");
    return displacement_misfit(c.problem, s.vertices, s.displacements);
  };
  // tests/data/objective_terms/observations.txt: two tip vertices of the registry's test box.
  t.example = {{"type", "observations"}, {"file", "observations.txt"}};
  return t;
}

}  // namespace tailor
