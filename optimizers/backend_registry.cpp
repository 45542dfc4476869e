// The optimizer back-end registry (optimizers/backend_registry.hpp).
#include "optimizers/backend_registry.hpp"

#include <stdexcept>

namespace tailor {

// The built-in back-ends' entry functions, listed from their files by
// cmake/tailorWriteRegistryList.cmake.
#define TAILOR_ENTRY(id) BackendEntry id##_backend_entry();
#include "tailor_builtin_backends.inc"
#undef TAILOR_ENTRY

namespace {

// Built once, on first use, and never changed: no lock needed after construction.
const std::vector<BackendEntry>& entries() {
  static const std::vector<BackendEntry> all = [] {
    std::vector<BackendEntry> out;
    for (BackendEntry (*entry)() : {
#define TAILOR_ENTRY(id) &id##_backend_entry,
#include "tailor_builtin_backends.inc"
#undef TAILOR_ENTRY
         }) {
      BackendEntry e = entry();
      if (e.name.empty() || !e.run) throw std::logic_error("optimizer back-end entry without a name or run");
      for (const BackendEntry& other : out)
        if (other.name == e.name)
          throw std::logic_error("optimizer back-end '" + e.name + "' registered twice");
      out.push_back(std::move(e));
    }
    return out;
  }();
  return all;
}

}  // namespace

const BackendEntry& find_backend(OptimizerBackend backend) {
  for (const BackendEntry& entry : entries())
    if (entry.name == backend.name()) return entry;
  std::string known;
  for (const BackendEntry& entry : entries()) known += (known.empty() ? "" : ", ") + entry.name;
  throw std::invalid_argument("unknown optimizer back-end '" + std::string(backend.name()) +
                              "' (known: " + known + ")");
}

std::vector<const BackendEntry*> registered_backends() {
  std::vector<const BackendEntry*> out;
  for (const BackendEntry& entry : entries()) out.push_back(&entry);
  return out;
}

std::string backends_with(bool BackendCapabilities::*capability) {
  std::vector<std::string> names;
  for (const BackendEntry& entry : entries())
    if (entry.capabilities.*capability) names.push_back(entry.name);
  std::string text;
  for (std::size_t k = 0; k < names.size(); ++k)
    text += (k == 0 ? "" : k + 1 == names.size() ? " or " : ", ") + names[k];
  return text.empty() ? "none" : text;
}

}  // namespace tailor
