// Scene files of every kind, as JSON text: each input goes to the parser `tailor` would pick
// for it (problems/cli/main.cpp): rods, rigid bodies, periodic cells (with a metamaterial
// "design"), material fits, damping designs, and otherwise the FEM scene with its "inverse" and
// "dynamics" sections. Relative paths resolve against scenes/, so the seeds' data files exist.
#include <cmath>
#include <nlohmann/json.hpp>

#include "fuzz/fuzz_support.hpp"
#include "problems/contact/rigid_scene.hpp"
#include "problems/damping_design/damping_design_scene.hpp"
#include "problems/homogenization/cell_scene.hpp"
#include "problems/json_text.hpp"
#include "problems/material_fit/material_fit_scene.hpp"
#include "problems/metamaterial/metamaterial_scene.hpp"
#include "problems/rods/rod_scene.hpp"
#include "problems/scene_node.hpp"

namespace {

using namespace tailor;

bool has_type(const nlohmann::json& document, const char* type) {
  const auto it = document.find("type");
  return it != document.end() && *it == type;
}

// Periodic cells are meshed while parsing. Grids the parser accepts (it refuses those that
// cannot fit, see tests/problems/parser_regression_test.cpp) may still take seconds to mesh and
// pair up; above this many grid cells an input is skipped, so that a slow but valid input is
// not reported as a hang.
constexpr double kMaxGridCells = 5000;

bool large_grid(const nlohmann::json& document) {
  const auto cell = document.find("cell");
  if (cell == document.end() || !cell->is_object()) return false;
  const auto grid = cell->find("grid");
  if (grid == cell->end() || !grid->is_array()) return false;
  double cells = 1.0;
  for (const auto& n : *grid)
    if (n.is_number()) cells *= std::abs(n.get<double>());
  return cells > kMaxGridCells;
}

void parse_any_scene(const std::string& text) {
  const std::string source = "fuzz.json";
  const nlohmann::json document = parse_json_or_discarded(text);
  const bool object = document.is_object();
  const SceneNode root(document, source, "");
  if (object && document.contains("rods")) {
    parse_rod_scene(root);
  } else if (object && document.contains("rigid_bodies")) {
    parse_rigid_scene(root, fuzz::kScenesDir);
  } else if (object && has_type(document, "periodic_cell")) {
    if (large_grid(document)) return;
    const CellScene cell = parse_cell_scene(root, fuzz::kScenesDir);
    if (cell.has_design) parse_metamaterial_design(root, cell);
  } else if (object && has_type(document, "material_fit")) {
    parse_material_fit_scene(root);
  } else if (object && document.contains("damping_design")) {
    parse_damping_design(root);
  } else {
    parse_scene(text, source, fuzz::kScenesDir);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = fuzz::as_text(data, size);
  fuzz::expect_clean([&] { parse_any_scene(text); });
  return 0;
}
