// "synthetic_observations": displacements of the selected vertices at the equilibrium with a
// true Young's modulus field, with optional Gaussian noise -- recovery studies with a known answer.
#include <random>

#include "problems/fem/inverse_problem.hpp"
#include "problems/fem/objective_terms/builtin_terms.hpp"
#include "problems/fem/scene_parsing.hpp"
#include "problems/fem/scene_selection.hpp"

namespace tailor {

ObjectiveTermType synthetic_observations_objective_term() {
  ObjectiveTermType t;
  t.type = "synthetic_observations";
  t.is_data = true;
  t.keys = {"vertices", "youngs_modulus", "noise", "seed"};
  t.required = {"vertices", "youngs_modulus"};
  t.parse = [](const SceneNode& node, const std::string& directory) {
    auto s = std::make_shared<SyntheticObservationsTerm>();
    s->vertices = parse_vertex_selector(node.at("vertices"), directory);
    s->youngs_modulus = parse_modulus_field(node.at("youngs_modulus"), directory);
    if (auto n = node.find("noise")) s->noise = n->non_negative();
    if (auto seed = node.find("seed")) s->seed = static_cast<unsigned>(seed->integer(0));
    return s;
  };
  t.build = [](const ObjectiveTermContext& c) {
    const auto& s = c.settings<SyntheticObservationsTerm>();
    const Mesh& mesh = c.problem.setup.mesh;
    const std::vector<int> vertices = select_vertices(c.scene, mesh, s.vertices);
    const Eigen::VectorXd truth = modulus_field_values(c.scene, c.problem.setup, s.youngs_modulus);
    c.record_truth(truth, s.youngs_modulus.key);
    StaticSetup true_setup = c.problem.setup;
    true_setup.youngs_modulus = truth;
    const StaticSolution solution = solve_static(true_setup);
    if (!solution.converged)
      throw_scene_error(c.scene, s.youngs_modulus.key,
                        "the forward solve with this Young's modulus failed (" + solution.status + ": " +
                            solution.message + ")");
    Eigen::MatrixXd observed(static_cast<Eigen::Index>(vertices.size()), mesh.dim());
    for (std::size_t i = 0; i < vertices.size(); ++i)
      observed.row(static_cast<Eigen::Index>(i)) = solution.displacement.row(vertices[i]);
    if (s.noise > 0.0) {
      const double sigma = s.noise * observed.rowwise().norm().maxCoeff();
      std::mt19937 rng(s.seed);
      std::normal_distribution<double> normal(0.0, sigma);
      for (Eigen::Index k = 0; k < observed.size(); ++k) observed.data()[k] += normal(rng);
    }
    return displacement_misfit(c.problem, vertices, observed);
  };
  t.example = {{"type", "synthetic_observations"},
               {"vertices", {{"plane", {{"axis", "z"}, {"value", 1}}}}},
               {"youngs_modulus", {{"value", 1e5}, {"gradient", {0.1, 0.0, 0.0}}}},
               {"noise", 0.01}};
  return t;
}

}  // namespace tailor
