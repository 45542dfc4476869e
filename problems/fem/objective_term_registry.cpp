#include "problems/fem/objective_term_registry.hpp"

#include <mutex>
#include <stdexcept>
#include <variant>

#include "problems/fem/inverse_problem.hpp"
#include "problems/fem/scene_parsing.hpp"
#include "problems/fem/scene_selection.hpp"

namespace tailor {
namespace {

struct Registry {
  std::mutex mutex;
  std::vector<std::shared_ptr<const ObjectiveTermType>> types;
};

Registry& registry() {
  static Registry instance;
  return instance;
}

template <std::size_t... I>
bool is_builtin_type(const std::string& type, std::index_sequence<I...>) {
  return ((type == std::variant_alternative_t<I, ObjectiveTerm>::kType) || ...);
}

}  // namespace

std::vector<int> ObjectiveTermContext::vertices(const char* key) const {
  return select_vertices(scene, problem.setup.mesh, parse_vertex_selector(node.at(key), scene.directory));
}

Eigen::MatrixXi ObjectiveTermContext::facets(const char* key) const {
  return select_boundary_facets(scene, problem.setup.mesh,
                                parse_vertex_selector(node.at(key), scene.directory));
}

void register_objective_term(ObjectiveTermType type) {
  if (type.type.empty()) throw std::logic_error("register_objective_term: the type needs a name");
  if (!type.build)
    throw std::logic_error("register_objective_term: \"" + type.type + "\" has no build function");
  if (is_builtin_type(type.type, std::make_index_sequence<std::variant_size_v<ObjectiveTerm>>()))
    throw std::logic_error("register_objective_term: \"" + type.type +
                           "\" is one of tailor's own term types");
  for (const std::string& key : type.required) {
    bool listed = false;
    for (const std::string& k : type.keys) listed = listed || k == key;
    if (!listed)
      throw std::logic_error("register_objective_term: \"" + type.type + "\" requires \"" + key +
                             "\", which is not among its keys");
  }
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  for (const auto& existing : r.types)
    if (existing->type == type.type)
      throw std::logic_error("register_objective_term: \"" + type.type + "\" is registered already");
  r.types.push_back(std::make_shared<const ObjectiveTermType>(std::move(type)));
}

std::vector<std::string> registered_objective_term_types() {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  std::vector<std::string> out;
  for (const auto& type : r.types) out.push_back(type->type);
  return out;
}

std::shared_ptr<const ObjectiveTermType> find_objective_term_type(const std::string& type) {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  for (const auto& t : r.types)
    if (t->type == type) return t;
  return nullptr;
}

}  // namespace tailor
