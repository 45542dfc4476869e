#pragma once
// Pieces of the scene parser shared by the static part (scene.cpp) and the inverse section
// (inverse_scene.cpp). Internal to problems/: every failure is a SceneError naming the key path.
#include <optional>
#include <string>
#include <vector>

#include "problems/fem/inverse_scene.hpp"
#include "problems/fem/scene.hpp"
#include "problems/scene_node.hpp"

namespace tailor {

// `path` relative to the scene's folder (unchanged when absolute or when directory is empty).
std::string resolve_scene_path(const std::string& directory, const std::string& path);

// Non-empty, non-comment ('#') lines of a small data file, split into whitespace-separated
// tokens, with their 1-based line numbers. `node` names the key that gave the path.
struct DataLine {
  int line;
  std::vector<std::string> tokens;
};
std::vector<DataLine> read_data_file(const SceneNode& node, const std::string& path);

std::optional<double> parse_number(const std::string& token);  // finite numbers only
std::optional<int> parse_vertex_id(const std::string& token);  // integers >= 0

// Every whitespace-separated number of the file `node` names (relative to `directory`), each
// > 0; at least one.
std::vector<double> read_positive_values(const SceneNode& node, const std::string& directory);

VertexSelector parse_vertex_selector(const SceneNode& node, const std::string& directory);

// Refuses, at `node` (the cell counts), a generated mesh of `elements` elements that cannot be
// built: more elements than int indices count, or a model larger than this machine's memory.
// Called before the mesh is allocated.
void check_mesh_fits(const SceneNode& node, double elements, int dim);

// A Young's modulus field (ModulusField): a number > 0, {"materials": [...]}, {"file": path} or
// an expression {"value", "gradient", "inclusions"} (inverse_scene.cpp; docs/scenes.md).
ModulusField parse_modulus_field(const SceneNode& node, const std::string& directory);

// A "handles" objective term (inverse_handles.cpp).
HandlesTerm parse_handles_term(const SceneNode& node, const std::string& directory);

// The "inverse" section (inverse_scene.cpp).
InverseSpec parse_inverse_section(const SceneNode& node, const std::string& directory);
// The same, where the program adds data terms of its own (problems/fem/study.hpp): the list may
// then hold none (or be empty).
InverseSpec parse_inverse_section(const SceneNode& node, const std::string& directory, bool other_data_terms);
// The "dynamics" section (dynamic_scene.cpp).
DynamicsSpec parse_dynamics_section(const SceneNode& node, const std::string& directory);

}  // namespace tailor
