#include "problems/fem/linear_solver_choice.hpp"

#include <map>
#include <stdexcept>

namespace tailor {
namespace {

std::map<std::string, LinearSolverFactory>& factories() {
  static std::map<std::string, LinearSolverFactory> registry;
  return registry;
}

}  // namespace

void register_linear_solver(const std::string& name, LinearSolverFactory factory) {
  if (!factory) throw std::invalid_argument("register_linear_solver: no factory for '" + name + "'");
  factories()[name] = factory;
}

void unregister_linear_solver(const std::string& name) { factories().erase(name); }

bool linear_solver_registered(const std::string& name) { return factories().count(name) > 0; }

LinearSolverPtr make_linear_solver(const LinearSolverChoice& choice) {
  const auto found = factories().find(choice.name);
  if (found == factories().end()) {
    if (choice.name == "petsc")
      throw std::invalid_argument(
          "this tailor has no PETSc back-end: build it with PETSc (CMake option -DTAILOR_WITH_PETSC=ON; "
          "needs "
          "PETSc found by pkg-config, MPI and mpiexec, see docs/petsc.md) and run bin/tailor, which "
          "registers it");
    throw std::invalid_argument("no linear solver '" + choice.name + "' is registered in this program");
  }
  LinearSolverPtr solver = found->second(choice);
  if (!solver)
    throw std::invalid_argument("the factory of linear solver '" + choice.name + "' returned none");
  return solver;
}

Vector free_vertex_coordinates(const Elimination& elimination, int dim, const Vector& positions) {
  const int n = elimination.num_dofs(), m = elimination.num_free();
  if (dim < 1 || positions.size() != n || n % dim != 0 || m % dim != 0 || !elimination.is_selection())
    return {};
  // dof_of[j]: the DOF that free unknown j is (each free unknown exactly one DOF).
  std::vector<int> dof_of(static_cast<std::size_t>(m), -1);
  const std::vector<int>& begin = elimination.row_begin();
  const std::vector<int>& free = elimination.row_free();
  for (int i = 0; i < n; ++i)
    for (int k = begin[i]; k < begin[i + 1]; ++k) {
      int& dof = dof_of[static_cast<std::size_t>(free[k])];
      if (dof >= 0) return {};  // two DOFs share an unknown (a tie, not a selection of vertices)
      dof = i;
    }
  Vector coordinates(m);
  for (int j = 0; j < m; ++j) {
    const int dof = dof_of[static_cast<std::size_t>(j)];
    const int first = dof_of[static_cast<std::size_t>(j - j % dim)];
    // Unknown j must be component j % dim of the vertex of the block's first unknown.
    if (dof < 0 || first % dim != 0 || dof != first + j % dim) return {};
    coordinates[j] = positions[dof];
  }
  return coordinates;
}

void give_vertex_coordinates(LinearSolver& solver, const Elimination& elimination, int dim,
                             const Vector& positions) {
  const Vector coordinates = free_vertex_coordinates(elimination, dim, positions);
  if (coordinates.size() > 0) solver.set_vertex_coordinates(dim, coordinates);
}

}  // namespace tailor
