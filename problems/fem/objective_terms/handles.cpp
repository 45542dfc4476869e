// "handles": material design with handles (Xu et al. 2015; docs/scenes.md, "Material design with
// handles"). Its settings are HandlesTerm (inverse_handles_spec.hpp); the inverse problem
// constrains the handle vertices and appends their displacements to the design
// (inverse_handles.hpp) before the objective terms are built, so its build only hands over the
// objective made there.
#include "problems/fem/inverse_handles.hpp"
#include "problems/fem/inverse_problem.hpp"
#include "problems/fem/objective_terms/builtin_terms.hpp"
#include "problems/fem/scene_parsing.hpp"

namespace tailor {

ObjectiveTermType handles_objective_term() {
  ObjectiveTermType t;
  t.type = "handles";
  t.is_data = true;
  t.keys = {"alpha", "beta", "handles"};
  t.required = {"handles"};
  t.parse = [](const SceneNode& node, const std::string& directory) {
    return std::make_shared<HandlesTerm>(parse_handles_term(node, directory));
  };
  t.build = [](const ObjectiveTermContext& c) -> BuiltObjectiveTerm { return c.problem.handles->objective; };
  t.example = {{"type", "handles"},
               {"alpha", 1e-4},
               {"beta", 400},
               {"handles",
                {{{"vertices", {{"box", {{"min", {4, 0, 0}}, {"max", {4, 1, 1}}}}}},
                  {"force", {0, 0, -50}},
                  {"displacement", {0, 0, -0.05}}}}}};
  return t;
}

}  // namespace tailor
