#include "problems/fem/objective_term_registry.hpp"

#include <mutex>
#include <stdexcept>

#include "problems/fem/inverse_problem.hpp"
#include "problems/fem/scene_parsing.hpp"
#include "problems/fem/scene_selection.hpp"

namespace tailor {

// The built-in types' entry functions, listed from problems/fem/objective_terms/ by
// cmake/tailorWriteRegistryList.cmake.
#define TAILOR_ENTRY(id) ObjectiveTermType id##_objective_term();
#include "tailor_builtin_objective_terms.inc"
#undef TAILOR_ENTRY

namespace {

void check_entry(const ObjectiveTermType& type) {
  if (type.type.empty()) throw std::logic_error("register_objective_term: the type needs a name");
  if (!type.build)
    throw std::logic_error("register_objective_term: \"" + type.type + "\" has no build function");
  for (const std::string& key : type.required) {
    bool listed = false;
    for (const std::string& k : type.keys) listed = listed || k == key;
    if (!listed)
      throw std::logic_error("register_objective_term: \"" + type.type + "\" requires \"" + key +
                             "\", which is not among its keys");
  }
}

struct ObjectiveTermTable {
  std::mutex mutex;
  std::vector<std::shared_ptr<const ObjectiveTermType>> types;
  // The first `builtin` types are tailor's own (all of them while the constructor runs).
  std::size_t builtin = static_cast<std::size_t>(-1);

  ObjectiveTermTable() {
    for (ObjectiveTermType (*entry)() : {
#define TAILOR_ENTRY(id) &id##_objective_term,
#include "tailor_builtin_objective_terms.inc"
#undef TAILOR_ENTRY
         })
      add(entry());
    builtin = types.size();
  }
  // Under the lock, or from the constructor.
  void add(ObjectiveTermType type) {
    check_entry(type);
    for (std::size_t k = 0; k < types.size(); ++k)
      if (types[k]->type == type.type)
        throw std::logic_error("register_objective_term: \"" + type.type + "\" is " +
                               (k < builtin ? "one of tailor's own term types" : "registered already"));
    types.push_back(std::make_shared<const ObjectiveTermType>(std::move(type)));
  }
};

ObjectiveTermTable& objective_term_table() {
  static ObjectiveTermTable instance;
  return instance;
}

}  // namespace

std::vector<int> ObjectiveTermContext::vertices(const char* key) const {
  return select_vertices(scene, problem.setup.mesh, parse_vertex_selector(node.at(key), scene.directory));
}

Eigen::MatrixXi ObjectiveTermContext::facets(const char* key) const {
  return select_boundary_facets(scene, problem.setup.mesh,
                                parse_vertex_selector(node.at(key), scene.directory));
}

void ObjectiveTermContext::record_truth(const Eigen::VectorXd& youngs_modulus, const std::string& key) const {
  set_truth(scene, *building_, youngs_modulus, key);
}

void register_objective_term(ObjectiveTermType type) {
  ObjectiveTermTable& r = objective_term_table();
  const std::lock_guard<std::mutex> lock(r.mutex);
  r.add(std::move(type));
}

std::vector<std::string> objective_term_types() {
  ObjectiveTermTable& r = objective_term_table();
  const std::lock_guard<std::mutex> lock(r.mutex);
  std::vector<std::string> out;
  for (const auto& type : r.types) out.push_back(type->type);
  return out;
}

std::shared_ptr<const ObjectiveTermType> find_objective_term_type(const std::string& type) {
  ObjectiveTermTable& r = objective_term_table();
  const std::lock_guard<std::mutex> lock(r.mutex);
  for (const auto& t : r.types)
    if (t->type == type) return t;
  return nullptr;
}

}  // namespace tailor
