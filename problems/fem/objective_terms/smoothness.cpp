// "smoothness": a regularization of the designed per-element field, penalizing its jumps (of
// log E or of E) across shared facets (objectives/material_smoothness.hpp).
#include "problems/fem/inverse_problem.hpp"
#include "problems/fem/objective_terms/builtin_terms.hpp"
#include "problems/fem/scene_selection.hpp"

namespace tailor {

ObjectiveTermType smoothness_objective_term() {
  ObjectiveTermType t;
  t.type = "smoothness";
  t.keys = {"on", "weighting"};
  t.parse = [](const SceneNode& node, const std::string&) {
    auto s = std::make_shared<SmoothnessTerm>();
    if (auto on = node.find("on")) s->logarithmic = on->choice({"log", "value"}) == "log";
    if (auto w = node.find("weighting"))
      s->weighting = w->choice({"unit", "facet"}) == "unit" ? AdjacencyWeighting::unit
                                                            : AdjacencyWeighting::facet_over_distance;
    return s;
  };
  t.build = [](const ObjectiveTermContext& c) -> BuiltObjectiveTerm {
    const auto& s = c.settings<SmoothnessTerm>();
    try {
      return std::make_shared<MaterialSmoothness>(c.problem.setup.mesh, c.problem.youngs_offset, 1.0,
                                                  MaterialSmoothnessOptions{s.weighting, s.logarithmic});
    } catch (const std::invalid_argument& e) {
      throw_scene_error(c.scene, c.node.path(), e.what());
    }
  };
  t.example = {{"type", "smoothness"}, {"on", "log"}, {"weighting", "facet"}};
  return t;
}

}  // namespace tailor
