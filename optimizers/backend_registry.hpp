#pragma once
// The optimizer back-ends minimize() runs, with what each accepts. Each of tailor's back-ends
// registers itself from its own file under optimizers/ by defining, at namespace tailor scope,
//     BackendEntry <name>_backend_entry() { ... }
// (a file may define several); the build lists them (cmake/tailorWriteRegistryList.cmake) in
// file order. Code above optimizers/ asks the capabilities here instead of naming back-ends, and
// the optimizer tests run every registered back-end.
#include <functional>
#include <string>
#include <vector>

#include "optimizers/optimizer.hpp"

namespace tailor {

namespace detail {
class Tracker;          // optimizers/tracker.hpp
struct BackendOutcome;  // optimizers/backend_detail.hpp
}  // namespace detail

struct BackendCapabilities {
  bool bounds = false;                  // box bounds (Bounds)
  bool inequality_constraints = false;  // Constraint with equality = false
  bool equality_constraints = false;    // Constraint with equality = true
  bool exact_hessian = false;           // OptimizerOptions::exact_hessian (from Hessian-vector products)
};

struct BackendEntry {
  std::string name;     // as scenes write it
  std::string summary;  // one line
  BackendCapabilities capabilities;
  // Runs the back-end from z0 (already projected onto the bounds); the Tracker holds the
  // functional, bounds, constraints and options. Private to optimizers/.
  detail::BackendOutcome (*run)(detail::Tracker& tracker, const Vector& z0) = nullptr;
};

// The entry of a registered back-end; std::invalid_argument naming the registered ones otherwise.
const BackendEntry& find_backend(OptimizerBackend backend);
// Every registered back-end, in the order of their files.
std::vector<const BackendEntry*> registered_backends();
// The registered back-ends with a capability, for messages: "ipopt, nlopt_mma or nlopt_slsqp".
std::string backends_with(bool BackendCapabilities::*capability);

// Called once before Ipopt's first solve in the process. Debian's Ipopt solves with the
// sequential MUMPS, whose symbols a program that also links PETSc's MPI MUMPS (the tailor
// command line with the PETSc back-end) resolves to the MPI build: that one aborts unless MPI
// is initialized, so such a program sets a prelude that starts MPI (problems/cli/petsc_command_line.cpp).
void set_ipopt_prelude(std::function<void()> prelude);

}  // namespace tailor
