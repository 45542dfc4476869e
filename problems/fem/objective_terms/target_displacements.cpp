// "target_displacements": the selected vertices should move by one given displacement.
#include "problems/fem/inverse_problem.hpp"
#include "problems/fem/objective_terms/builtin_terms.hpp"
#include "problems/fem/scene_parsing.hpp"
#include "problems/fem/scene_selection.hpp"

namespace tailor {

ObjectiveTermType target_displacements_objective_term() {
  ObjectiveTermType t;
  t.type = "target_displacements";
  t.is_data = true;
  t.keys = t.required = {"vertices", "displacement"};
  t.parse = [](const SceneNode& node, const std::string& directory) {
    auto s = std::make_shared<TargetDisplacementsTerm>();
    s->vertices = parse_vertex_selector(node.at("vertices"), directory);
    s->displacement = node.at("displacement").vector();
    return s;
  };
  t.build = [](const ObjectiveTermContext& c) {
    const auto& s = c.settings<TargetDisplacementsTerm>();
    const Mesh& mesh = c.problem.setup.mesh;
    check_dimension(c.scene, mesh, s.displacement, c.node.path() + ".displacement");
    const std::vector<int> vertices = select_vertices(c.scene, mesh, s.vertices);
    const Eigen::MatrixXd targets =
        s.displacement.transpose().replicate(static_cast<Eigen::Index>(vertices.size()), 1);
    return displacement_misfit(c.problem, vertices, targets);
  };
  t.example = {{"type", "target_displacements"},
               {"vertices", {{"plane", {{"axis", "x"}, {"value", 4}}}}},
               {"displacement", {0.0, 0.0, -0.02}}};
  return t;
}

}  // namespace tailor
