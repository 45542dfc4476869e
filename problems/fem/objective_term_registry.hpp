#pragma once
// The objective term types of inverse scenes: what a scene names by "type" in its "objective"
// list. tailor's own (problems/fem/objective_terms/: target_displacements, observations,
// synthetic_observations, smoothness, tikhonov, handles) and a program's are entries of one
// registry with one shape. An entry lists its keys besides "type" and "weight" (any other key is
// an error naming its path), may parse them into typed settings when the scene is read (files,
// selectors: bad input fails before any solve), and builds its Objective when the inverse problem
// is built, with the mesh and the design at hand:
//
//   register_objective_term({"compliance", true, {"faces"}, {"faces"}, [](const ObjectiveTermContext& c) {
//     return std::make_shared<MyCompliance>(c.problem.setup, c.facets("faces"));
//   }});
//
// A program registers before the scene is read (read_scene, Study::from_file). The objective adds
// weight / scale * term, where the build returns the scale (1 unless it says otherwise; the data
// terms return |u*|^2, so that their weight multiplies a relative misfit). A new built-in type is
// one file in problems/fem/objective_terms/ whose entry function is
// `ObjectiveTermType <type>_objective_term()`; the build lists it (cmake/tailorWriteRegistryList.cmake)
// and tests/problems/objective_term_registry_test.cpp checks it through its `example`.
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "objectives/objective.hpp"
#include "problems/scene_node.hpp"

namespace tailor {

struct Scene;           // problems/fem/scene.hpp
struct InverseProblem;  // problems/fem/inverse_problem.hpp

// A term's settings as its type's `parse` read them from the scene (each type derives its own).
struct ObjectiveTermSettings {
  virtual ~ObjectiveTermSettings() = default;
};

// What a term's build sees: the scene, the problem built so far (setup with mesh, loads and
// supports; the full-load model with its parameter layout; youngs_offset; the design's
// parameterization; handles), the term's JSON with its key path ("inverse.objective[2]") and the
// settings its type parsed (none without a parse).
class ObjectiveTermContext {
 public:
  ObjectiveTermContext(const Scene& scene, InverseProblem& problem, SceneNode node,
                       const ObjectiveTermSettings* settings)
      : scene(scene), problem(problem), node(std::move(node)), settings_(settings), building_(&problem) {}

  const Scene& scene;
  const InverseProblem& problem;
  SceneNode node;

  // A vertex selector member of the term (scene format: plane, box, list, boundary, file),
  // resolved against the mesh: vertex ids, increasing. Throws SceneError naming the key.
  std::vector<int> vertices(const char* key) const;
  // Boundary facets whose vertices are all selected by the selector member `key`.
  Eigen::MatrixXi facets(const char* key) const;
  // The settings the type's parse returned, as the type's own struct.
  template <class Settings>
  const Settings& settings() const {
    const auto* typed = dynamic_cast<const Settings*>(settings_);
    if (!typed) throw std::logic_error(node.path() + ": the term's settings are not of the type its build expects");
    return *typed;
  }
  // Records the true per-element Young's modulus (for the report's error figures); a second
  // source must agree with the first (SceneError naming `key` otherwise).
  void record_truth(const Eigen::VectorXd& youngs_modulus, const std::string& key) const;

 private:
  const ObjectiveTermSettings* settings_;
  InverseProblem* building_;
};

// What a build returns: the objective and the scale its weight is divided by.
struct BuiltObjectiveTerm {
  template <class T, class = std::enable_if_t<std::is_base_of_v<Objective, T>>>
  BuiltObjectiveTerm(std::shared_ptr<T> objective, double scale = 1.0)  // NOLINT: implicit on purpose
      : objective(std::move(objective)), scale(scale) {}
  ObjectivePtr objective;
  double scale = 1.0;
};

struct ObjectiveTermType {
  std::string type;                   // its "type" in the scene
  bool is_data = false;               // fits data (a scene needs at least one data term)
  std::vector<std::string> keys;      // its keys besides "type" and "weight"; any other is an error
  std::vector<std::string> required;  // of those, the ones it must have
  // The objective; throw SceneError through context.node.fail(...) for bad values.
  std::function<BuiltObjectiveTerm(const ObjectiveTermContext& context)> build;
  // Optional: reads the keys when the scene is read (relative paths start at `directory`) into
  // the settings that build receives. Keys and required keys are checked before it runs.
  std::function<std::shared_ptr<ObjectiveTermSettings>(const SceneNode& node, const std::string& directory)>
      parse{};
  // A term object of this type for the registry's test scene: a 4 x 1 x 1 box of linear
  // material, clamped at x = 0, pulled down at x = 4 by a traction, with one log-E design
  // variable per element (tests/problems/objective_term_registry_test.cpp). Every built-in has one.
  nlohmann::json example{};
};

// Throws std::logic_error for an empty or taken type (tailor's own included), without build, or
// with a required key that is not among its keys.
void register_objective_term(ObjectiveTermType type);
// Every type's name: tailor's own (in file order), then the program's in registration order.
std::vector<std::string> objective_term_types();
// Null when `type` is none.
std::shared_ptr<const ObjectiveTermType> find_objective_term_type(const std::string& type);

}  // namespace tailor
