#pragma once
// Every registered optimizer back-end (optimizers/backend_registry.hpp), for parameterized tests:
// a new back-end is tested without being listed.
#include <vector>

#include "optimizers/backend_registry.hpp"

namespace tailor::test {

inline std::vector<OptimizerBackend> every_backend() {
  std::vector<OptimizerBackend> out;
  for (const BackendEntry* entry : registered_backends()) out.push_back(parse_optimizer_backend(entry->name));
  return out;
}

}  // namespace tailor::test
