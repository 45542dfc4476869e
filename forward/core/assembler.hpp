#pragma once
// ReducedAssembler: evaluates a Model in the free unknowns y of its elimination
// (x = x0 + S y): energy, reduced gradient S^T g and the reduced Hessian S^T H S.
//
// The Hessian is stored as the upper triangle of a compressed column matrix whose pattern is
// computed once from the terms' hessian_pattern(); every evaluation only gathers element
// values into it through a precomputed entry -> slots map (no triplet sorting per iteration;
// the gather runs in parallel because every matrix entry is written by one thread).
//
// Constant Hessians are evaluated once: a term whose hessian_is_constant() keeps the slot
// values it wrote while p (compared exactly), its hessian_revision() and the Hessian mode are
// unchanged, so a dynamic step assembles only the terms that depend on the state (the mass
// and Rayleigh damping of a nonlinear solid, say). Its energy and gradient are still evaluated.
// Their slots are also summed into matrix entries once: the gather keeps the constant terms'
// entry sums and adds only the other terms' slots to them (in a dynamic step of a nonlinear
// solid, the mass and damping slots outnumber the elastic ones 1.7 to 1).
//
// Long rows of S (more than kShortRow entries: the collocation rows of a meshless
// transformation, a modal basis) are not imaged slot by slot, which costs the product of the
// two rows' lengths per slot in memory and time (a clamp of 121 collocation nodes: 15k images
// per slot). The slots that touch one are summed into an x-space matrix H_c and reduced as
// upper(S^T (H_c S)), two sparse products whose patterns are computed once; a pure selection
// or short-row S takes the slot images alone, as before.
#include "forward/core/model.hpp"

namespace tailor {

class ReducedAssembler {
 public:
  explicit ReducedAssembler(const Model& model);
  // Over some terms only (the model still gives the state and the elimination), e.g. a
  // process's share of the elements in distributed assembly. Without `hessian` it evaluates
  // energies and gradients only (no pattern is built: a Hessian request is an error); without
  // `full_diagonal` the pattern holds the diagonal entries that the terms write, not all of them.
  ReducedAssembler(const Model& model, std::vector<const EnergyTerm*> terms, bool hessian = true,
                   bool full_diagonal = true);

  int num_free() const { return model_.elimination().num_free(); }
  const Model& model() const { return model_; }

  // Any of energy / reduced gradient / reduced upper-triangular Hessian at y. The Hessian
  // pointer must be a matrix previously obtained from hessian_pattern_matrix() (or null).
  void evaluate(const Vector& y, const Vector& p, double* energy, Vector* gradient_y,
                SparseMatrix* hessian_y, HessianMode mode = HessianMode::exact);

  // The low-rank part of the reduced Hessian, S^T F G F^T S (see LowRankHessian), at y.
  LowRankHessian low_rank_hessian(const Vector& y, const Vector& p, HessianMode mode = HessianMode::exact) const;

  // A zero-valued upper-triangular matrix with the reduced Hessian's pattern.
  SparseMatrix hessian_pattern_matrix() const { return pattern_; }
  // Hessian values the terms write per evaluation (the slots of their patterns).
  std::size_t num_slots() const { return buffer_.size(); }

 private:
  const Model& model_;
  std::vector<const EnergyTerm*> terms_;
  bool hessian_ = true;
  std::vector<std::size_t> term_slot_begin_;  // per term: first slot in buffer_
  std::vector<double> buffer_;                // per-slot values written by the terms
  // Constant-Hessian terms whose slots in buffer_ hold their Hessian at cached_p_, with the
  // revision and mode they were written with.
  struct CachedHessian {
    bool valid = false;
    std::uint64_t revision = 0;
    HessianMode mode = HessianMode::exact;
  };
  std::vector<CachedHessian> cached_;
  Vector cached_p_;
  // Matrix entry e of pattern_ = sum over t in [begin[e], begin[e+1]) of
  // weight[t] * buffer_[slot[t]] (weights omitted when all are 1), in two groups: the slots of
  // the terms whose Hessian was constant when the assembler was built, and all others.
  struct Gather {
    std::vector<std::int64_t> begin;
    std::vector<int> slot;
    std::vector<double> weight;
    bool unit_weights = true;
    bool empty() const { return slot.empty(); }
    // out[e] = (add ? out[e] : 0) + the entry's sum, for every entry e.
    void sum(const double* slot_values, double* out, bool add) const;
  };
  Gather constant_gather_, state_gather_;
  std::vector<char> constant_term_;  // per term: its slots are in constant_gather_
  // The constant group's entry sums while none of its terms has rewritten its slots (the
  // mass and Rayleigh damping of a dynamic step: most of the slots, gathered once).
  std::vector<double> constant_sums_;
  bool constant_sums_valid_ = false;
  // values += upper(S^T H_c S) for the slots that touch a long row of S (see the top).
  struct CoupledProduct {
    int num_free = 0;
    std::vector<int> s_begin, s_free;  // S's rows (copied: the products need them per evaluation)
    std::vector<double> s_weight;
    // H_c in compressed rows: row r is x-row h_row[r], its entries [h_begin[r], h_begin[r+1])
    // in x-columns h_col, each the sum of the slots h_gather lists for it.
    std::vector<int> h_row, h_col;
    std::vector<std::int64_t> h_begin;
    Gather h_gather;
    // T = H_c S, rows as H_c's, columns t_col (free unknowns, increasing per row).
    std::vector<std::int64_t> t_begin;
    std::vector<int> t_col;
    // Per free unknown a in r_free: the rows r of T with S(h_row[r], a) = weight, and the
    // offset in that row of its first column >= a; then the reduced entries (a, out_col) with
    // out_col >= a, at out_entry in the upper-triangular pattern.
    std::vector<int> r_free;
    std::vector<std::int64_t> a_begin, out_begin;
    std::vector<int> a_trow;
    std::vector<std::int64_t> a_tstart;
    std::vector<double> a_weight;
    std::vector<int> out_col, out_entry;
    bool empty() const { return h_row.empty(); }
    void add(const double* slot_values, double* values) const;
  };
  static constexpr int kShortRow = 8;
  // Builds coupled_ (out_entry excepted) for the given slots; returns the reduced entries
  // (a, b), a <= b, that it adds to, in out_col's order.
  std::vector<std::pair<int, int>> build_coupled_product(const HessianPattern& slots,
                                                         const std::vector<std::size_t>& coupled_slots);
  CoupledProduct coupled_;
  SparseMatrix pattern_;
};

}  // namespace tailor
