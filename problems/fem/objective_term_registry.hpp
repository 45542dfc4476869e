#pragma once
// Objective term types a program registers for the "objective" list of its inverse scenes, next
// to tailor's own (target_displacements, observations, ...). A registered type is named by its
// "type" in the scene; its other keys are the program's: the parser accepts exactly the keys
// the type lists (besides "type" and "weight"), and when the inverse problem is built the
// type's `build` turns the term's JSON into an Objective, with the mesh and the design at hand.
//
//   register_objective_term({"compliance", true, {"faces"}, [](const ObjectiveTermContext& c) {
//     return std::make_shared<MyCompliance>(c.problem.setup, c.vertices("faces"));
//   }});
//
// Register before the scene is read (read_scene, Study::from_file). The objective adds
// weight * term (no normalization: the term's own scale is what the weight multiplies).
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "objectives/objective.hpp"
#include "problems/scene_node.hpp"

namespace tailor {

struct Scene;           // problems/fem/scene.hpp
struct InverseProblem;  // problems/fem/inverse_problem.hpp

// What a registered term's build sees: the scene, the problem built so far (setup with mesh,
// loads and supports; the full-load model with its parameter layout; youngs_offset; the
// design's parameterization), and the term's JSON with its key path ("inverse.objective[2]").
struct ObjectiveTermContext {
  const Scene& scene;
  const InverseProblem& problem;
  SceneNode node;
  // A vertex selector member of the term (scene format: plane, box, list, boundary, file),
  // resolved against the mesh: vertex ids, increasing. Throws SceneError naming the key.
  std::vector<int> vertices(const char* key) const;
  // Boundary facets whose vertices are all selected by the selector member `key`.
  Eigen::MatrixXi facets(const char* key) const;
};

struct ObjectiveTermType {
  std::string type;                   // its "type" in the scene
  bool is_data = false;               // fits data (a scene needs at least one data term)
  std::vector<std::string> keys;      // its keys besides "type" and "weight"; any other is an error
  std::vector<std::string> required;  // of those, the ones it must have
  // The objective; throw SceneError through context.node.fail(...) for bad values.
  std::function<ObjectivePtr(const ObjectiveTermContext& context)> build;
};

// Throws std::logic_error for an empty or taken type (tailor's own included) or without build.
void register_objective_term(ObjectiveTermType type);
// The registered types (not tailor's own), in registration order; null when `type` is not one.
std::vector<std::string> registered_objective_term_types();
std::shared_ptr<const ObjectiveTermType> find_objective_term_type(const std::string& type);

}  // namespace tailor
