#pragma once
// A stand-in registered as the scene's "petsc" linear solver for tests that need no MPI:
// Eigen's SimplicialLDLT (not tailor's CHOLMOD path), so what it solves must match CHOLMOD's
// to round-off.
#include <Eigen/SparseCholesky>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "forward/solve/linear_solver.hpp"
#include "problems/fem/linear_solver_choice.hpp"
#include "problems/output_process.hpp"

namespace tailor::testing {

// Eigen's sparse LDL^T as a LinearSolver, recording what it was given.
class EigenLdlt final : public LinearSolver {
 public:
  explicit EigenLdlt(std::string options) : options_(std::move(options)) {}
  std::string name() const override { return "petsc"; }  // registered under the scene's name
  bool setup(const SparseMatrix& upper, std::string& message) override {
    ldlt_.compute(upper);
    ++setups;
    if (ldlt_.info() != Eigen::Success) message = "not positive definite";
    return ldlt_.info() == Eigen::Success;
  }
  LinearSolveStats solve(const Vector& b, double relative_tolerance, Vector& x) override {
    x = ldlt_.solve(b);
    ++solves;
    tolerances.push_back(relative_tolerance);
    LinearSolveStats s;
    s.converged = x.allFinite();
    s.relative_tolerance = relative_tolerance;
    return s;
  }
  LinearSolverInfo info() const override {
    LinearSolverInfo i;
    i.name = name();
    i.options = options_;
    i.krylov_method = "preonly";
    i.solves = solves;
    return i;
  }
  void set_vertex_coordinates(int d, const Vector& c) override { dim = d, coordinates = c; }
  int setups = 0, solves = 0, dim = 0;
  Vector coordinates;
  std::vector<double> tolerances;  // of every solve, in order

 private:
  std::string options_;
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Upper> ldlt_;
};

inline std::shared_ptr<EigenLdlt>& last_made() {
  static std::shared_ptr<EigenLdlt> solver;
  return solver;
}

inline LinearSolverPtr make_eigen_ldlt(const LinearSolverChoice& choice) {
  if (choice.options.find("-bad") != std::string::npos) throw std::invalid_argument("option -bad is unknown");
  last_made() = std::make_shared<EigenLdlt>(choice.options);
  return last_made();
}

// Registers the stand-in as "petsc" for one test.
struct RegisteredStandIn {
  RegisteredStandIn() { register_linear_solver("petsc", make_eigen_ldlt); }
  ~RegisteredStandIn() {
    unregister_linear_solver("petsc");
    last_made().reset();
    set_writes_output(true);
  }
};

}  // namespace tailor::testing
