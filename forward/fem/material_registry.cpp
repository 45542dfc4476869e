// The material registry (forward/fem/material_registry.hpp) and the name-based functions of
// forward/fem/material.hpp on top of it.
#include "forward/fem/material_registry.hpp"

#include <deque>
#include <mutex>
#include <ostream>
#include <stdexcept>

namespace tailor {

// The built-in materials' entry functions, one per file under forward/fem/materials/ that
// defines one (written by cmake/tailorWriteRegistryList.cmake).
#define TAILOR_ENTRY(id) MaterialEntry id##_material_entry();
#include "tailor_builtin_materials.inc"
#undef TAILOR_ENTRY

namespace {

struct Registry {
  std::mutex mutex;
  std::deque<MaterialEntry> entries;  // a deque: references stay valid as entries are added
};

void check_new_entry(const Registry& registry, const MaterialEntry& entry) {
  if (entry.name.empty()) throw std::invalid_argument("register_material: empty name");
  for (char c : entry.name)
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'))
      throw std::invalid_argument("register_material: '" + entry.name +
                                  "': a name has lowercase letters, digits and '_' only");
  if (!entry.make_2d || !entry.make_3d)
    throw std::invalid_argument("register_material: '" + entry.name +
                                "' needs both the 2D and the 3D factory");
  for (const MaterialEntry& other : registry.entries)
    if (other.name == entry.name)
      throw std::invalid_argument("register_material: a material named '" + entry.name +
                                  "' is registered already");
}

Registry& registry() {
  static Registry* const instance = [] {
    auto* r = new Registry;  // never destroyed: materials may be made during static destruction
    for (MaterialEntry (*entry)() : {
#define TAILOR_ENTRY(id) &id##_material_entry,
#include "tailor_builtin_materials.inc"
#undef TAILOR_ENTRY
         }) {
      MaterialEntry e = entry();
      check_new_entry(*r, e);
      r->entries.push_back(std::move(e));
    }
    return r;
  }();
  return *instance;
}

std::string name_list(const Registry& r) {
  std::string list;
  for (const MaterialEntry& entry : r.entries) list += (list.empty() ? "" : ", ") + entry.name;
  return list;
}

}  // namespace

void register_material(MaterialEntry entry) {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  check_new_entry(r, entry);
  r.entries.push_back(std::move(entry));
}

const MaterialEntry& find_material(MaterialKind kind) {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  for (const MaterialEntry& entry : r.entries)
    if (entry.name == kind.name()) return entry;
  throw std::invalid_argument("unknown material '" + std::string(kind.name()) + "' (expected one of " +
                              name_list(r) + ")");
}

std::vector<const MaterialEntry*> registered_materials() {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  std::vector<const MaterialEntry*> out;
  for (const MaterialEntry& entry : r.entries) out.push_back(&entry);
  return out;
}

template <int Dim>
std::unique_ptr<Material<Dim>> make_material(MaterialKind kind) {
  const MaterialEntry& entry = find_material(kind);
  if constexpr (Dim == 2)
    return entry.make_2d();
  else
    return entry.make_3d();
}

template std::unique_ptr<Material<2>> make_material<2>(MaterialKind);
template std::unique_ptr<Material<3>> make_material<3>(MaterialKind);

MaterialKind parse_material_kind(const std::string& name) {
  // The kind views the registry's copy of the name, which lives as long as the program.
  return MaterialKind(find_material(MaterialKind(name)).name);
}

std::string to_string(MaterialKind kind) { return std::string(kind.name()); }

std::vector<std::string> material_names() {
  std::vector<std::string> names;
  for (const MaterialEntry* entry : registered_materials()) names.push_back(entry->name);
  return names;
}

std::ostream& operator<<(std::ostream& out, MaterialKind kind) { return out << kind.name(); }

}  // namespace tailor
