#pragma once
// HessianShare: this process's part of the reduced Hessian in distributed assembly
// (LinearSolver::assembles_by_parts, docs/petsc.md "Distributed assembly").
//
// Every element goes to the process that owns one of its free unknowns (the solver's split of
// the rows, LinearSolver::owns_unknown), chosen by a hash of its smallest free unknown, so that
// the elements across two processes' rows are shared evenly; elements without free unknowns
// go nowhere. Terms
// that cannot be split by elements (EnergyTerm::share_by_elements false) go whole to the
// process that owns unknown 0. The share is assembled like the whole Hessian (upper triangle in
// the numbering of all free unknowns, ReducedAssembler over the share's terms), but its pattern
// holds only the entries its elements write: the processes' shares sum to H.
#include <memory>
#include <vector>

#include "forward/core/assembler.hpp"
#include "forward/solve/linear_solver.hpp"

namespace tailor {

class HessianShare {
 public:
  HessianShare(const Model& model, const LinearSolver& solver);

  // Assembles the share's Hessian at (y, p) in `mode` (energy and gradient are not evaluated).
  void assemble(const Vector& y, const Vector& p, HessianMode mode);
  const SparseMatrix& hessian() const { return hessian_; }
  // The terms of the share (split terms and whole ones) and its element slots.
  int num_terms() const { return static_cast<int>(terms_.size()); }
  std::size_t num_slots() const { return assembler_->num_slots(); }

 private:
  std::vector<std::unique_ptr<EnergyTerm>> owned_;  // the split terms
  std::vector<const EnergyTerm*> terms_;
  std::unique_ptr<ReducedAssembler> assembler_;
  SparseMatrix hessian_;
};

}  // namespace tailor
