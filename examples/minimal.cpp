// The smallest program against an installed tailor: it compiles against the public headers
// and links every library with its dependencies, which is what find_package(tailor) promises.
#include <cstdio>

#include "forward/core/elimination.hpp"
#include "forward/solve/blas_info.hpp"
#include "optimizers/backends.hpp"
#include "tailor_version.hpp"

int main() {
  std::printf("tailor %s\n", tailor::version_string);
  for (const tailor::BackendInfo& backend : tailor::optimizer_backends())
    std::printf("  %-6s %s\n", backend.name.c_str(), backend.version.c_str());
  std::printf("  BLAS   %s\n", tailor::blas_library_path().c_str());
  // Exercises the Eigen-typed API: 3 DOFs, the middle one fixed.
  const tailor::Elimination elimination = tailor::Elimination::dirichlet({1}, tailor::Vector::Zero(3));
  std::printf("  free DOFs of a 3-DOF chain with one fixed: %d\n", elimination.num_free());
  return elimination.num_free() == 2 ? 0 : 1;
}
