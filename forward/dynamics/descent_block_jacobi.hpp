#pragma once
// One evaluation pass of the descent solver (docs/dynamics.md, "The descent solver"): at the free
// unknowns y of a model (x = x0 + S y), the total potential E, its reduced gradient S^T dE/dx
// and the inverse of the block-Jacobi preconditioner D, the diagonal blocks of S^T H S with H the
// element-wise PSD-projected Hessian (Wang & Yang 2016, section 4; docs/dynamics.md, "The descent solver").
//
// Every term is evaluated once per pass, energy, gradient and (for terms whose Hessian depends
// on the state) element Hessians together: the FEM terms do it in their element loop
// (forward/fem/element_loop.hpp), so the pass is parallel and its result is the same for every
// thread count. The block entries are then summed from the slots that land in a diagonal
// block, in a fixed order per block. Terms with a constant Hessian (inertia, Rayleigh damping)
// write their slots once per parameter vector and revision, and their block sums are kept.
//
// A block is one vertex's free unknowns (block_size DOFs per vertex, interleaved: DOF
// block_size * v + k); a vertex with some components fixed has a smaller block, padded with
// the identity. The elimination must be a selection (Dirichlet conditions); periodic or
// handle constraints mix vertices and are refused.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "forward/core/model.hpp"

namespace tailor {

// The results of one pass at y.
struct DescentEvaluation {
  double energy = 0.0;
  // Round-off level of `energy`: 1000 eps times the sum of the terms' |energies| (a gravity
  // potential of absolute heights is large against the changes of an iteration).
  double energy_roundoff = 0.0;
  Vector gradient;                   // S^T dE/dx (force units), size num_free
  std::vector<double> block_inverse; // D^-1, block_size^2 values per block, row-major
};

class BlockJacobiPass {
 public:
  // Throws std::invalid_argument when the elimination is not a selection or block_size is not
  // 1, 2 or 3, or the model's DOF count is not a multiple of block_size.
  BlockJacobiPass(const Model& model, int block_size);

  const Model& model() const { return model_; }
  int num_free() const { return model_.elimination().num_free(); }
  int num_blocks() const { return static_cast<int>(block_free_.size()) / block_size_; }
  int block_size() const { return block_size_; }
  // block_size free indices per block (-1: padding), the layout of DescentEvaluation::block_inverse.
  const std::vector<int>& block_free() const { return block_free_; }

  // Energy, reduced gradient and (when with_preconditioner) D^-1 at (y, p) into `out`.
  void evaluate(const Vector& y, const Vector& p, DescentEvaluation& out, bool with_preconditioner);
  // direction = D^-1 gradient (reduced vectors), with D^-1 from an evaluation.
  void apply_inverse(const DescentEvaluation& at, const Vector& gradient, Vector& direction) const;

  // Bytes a pass moves through memory, counted from the arrays it streams (state, gradients,
  // Hessian slots written and read back, block sums): the figure descent_bench compares with
  // the measured bandwidth. Mesh and material arrays the terms read are not included.
  std::size_t bytes_per_pass(bool with_preconditioner) const;
  std::size_t state_slots() const { return state_slot_count_; }

 private:
  // Block entries as sums of slot values: entry e = sum of slots[begin[e] .. begin[e+1]).
  struct BlockGather {
    std::vector<std::int64_t> begin;
    std::vector<std::int64_t> slot;
    void sum(const std::vector<double>& slot_values, double* entries, bool add) const;
  };
  void invert_blocks(std::vector<double>& inverse) const;

  const Model& model_;
  int block_size_;
  std::vector<int> block_free_;  // block_size per block: the free index of each component, -1 = padding
  std::vector<std::size_t> term_slot_begin_;
  std::vector<char> term_constant_;
  std::vector<double> slots_;   // every term's Hessian slots, one buffer
  BlockGather constant_gather_, state_gather_;
  std::vector<double> constant_sums_, block_sums_;
  // Key of the constant terms' slots and sums: p and the terms' revisions.
  bool constant_valid_ = false;
  Vector constant_p_;
  std::vector<std::uint64_t> constant_revisions_;
  std::size_t state_slot_count_ = 0;
};

}  // namespace tailor
