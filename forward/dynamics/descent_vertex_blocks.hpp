#pragma once
// The vertex-block rule of the descent solver (docs/dynamics.md, "The GPU path"): the model's
// incremental potential laid out as the plain arrays of descent_vertex_block_kernels.hpp, and
// one pass evaluated on the host with those kernels (the same per-item code the CUDA device
// runs, so that CPU and device iterates agree to round-off).
//
// Models it takes: Dirichlet-only eliminations (a selection, each free unknown moving one DOF,
// vertices of 3 DOFs), terms that are either tet ElasticTerm<3> of a stable Neo-Hookean or
// StVK material (one material for all) or have a constant Hessian (inertia, Rayleigh damping,
// gravity, loads), and no term that bounds a step (the constant terms bound none). Anything else
// is refused with the reason (VertexBlockModel::check).
#include <cstdint>
#include <string>
#include <vector>

#include "forward/core/model.hpp"
#include "forward/dynamics/descent_vertex_block_kernels.hpp"

namespace tailor {

class VertexBlockModel {
 public:
  // Throws std::invalid_argument with check()'s reason when the model is not covered.
  explicit VertexBlockModel(const Model& model);
  // Empty when the rule covers the model, else why not.
  static std::string check(const Model& model);

  // At the start of a solve from y: the tets' Lame parameters and A (when p or a constant
  // term's revision changed since the last call: returns true, so a device copy is refreshed),
  // and the constant part's e0, g0 = S^T grad E_c, y0 = y and the start's positions.
  bool prepare(const Vector& p, const Vector& y);

  // The layout over this object's host arrays (valid until the next prepare).
  descent_kernels::VertexBlockLayout layout() const;
  const Model& model() const { return model_; }
  int num_free() const { return num_free_; }
  int num_tets() const { return static_cast<int>(tet_volume_.size()); }
  int num_vertices() const { return model_.num_dofs() / 3; }
  // The constant part's value at y0, and the sum of its terms' |energies| there (for the
  // round-off level of E, as in DescentEvaluation::energy_roundoff).
  double e0() const { return e0_; }
  double constant_magnitude() const { return constant_magnitude_; }
  const std::vector<double>& start_positions() const { return positions_; }

  // Host arrays, for a device copy.
  const std::vector<int>& tet_vertex() const { return tet_vertex_; }
  const std::vector<double>& tet_shape() const { return tet_shape_; }
  const std::vector<double>& tet_volume() const { return tet_volume_; }
  const std::vector<double>& tet_lame() const { return tet_lame_; }
  const std::vector<int>& block_vertex() const { return block_vertex_; }
  const std::vector<int>& block_free() const { return block_free_; }
  const std::vector<int>& incidence_begin() const { return incidence_begin_; }
  const std::vector<int>& incidence() const { return incidence_; }
  const std::vector<double>& constant_blocks() const { return constant_blocks_; }
  const std::vector<int>& a_begin() const { return a_begin_; }
  const std::vector<int>& a_col() const { return a_col_; }
  const std::vector<double>& a_value() const { return a_value_; }
  const std::vector<double>& g0() const { return g0_; }
  const std::vector<double>& y0() const { return y0_; }

 private:
  const Model& model_;
  int material_ = descent_kernels::kNeoHookean;
  int num_free_ = 0;
  std::vector<const EnergyTerm*> constant_terms_;
  std::vector<std::pair<const EnergyTerm*, int>> elastic_terms_;  // and the index of its first tet
  std::vector<int> tet_vertex_;
  std::vector<double> tet_shape_, tet_volume_, tet_lame_;
  std::vector<int> block_vertex_, block_free_, incidence_begin_, incidence_;
  std::vector<int> free_of_dof_;
  // Constant part.
  std::vector<double> constant_blocks_, a_value_, g0_, y0_, positions_;
  std::vector<int> a_begin_, a_col_;
  std::vector<int> a_slot_begin_, a_slot_;  // CSR entry e = sum of slot values a_slot_[a_slot_begin_[e]..]
  std::vector<double> slot_values_;
  double e0_ = 0.0, constant_magnitude_ = 0.0;
  bool parameters_valid_ = false;
  Vector parameters_p_;
  std::vector<std::uint64_t> revisions_;
};

// One pass of the rule on the host: energy, reduced gradient and block inverses at y, each
// item by the shared kernels (parallel over items, the same result for every thread count).
class VertexBlockHostPass {
 public:
  explicit VertexBlockHostPass(const VertexBlockModel& model) : model_(model) {}
  struct Result {
    double energy = 0.0, energy_roundoff = 0.0;
    Vector gradient;
    std::vector<double> block_inverse;  // 9 per block
  };
  void evaluate(const Vector& y, Result& out, bool with_blocks);
  // direction = D^-1 gradient.
  void apply_inverse(const Result& at, const Vector& gradient, Vector& direction) const;

 private:
  const VertexBlockModel& model_;
  std::vector<double> positions_, tet_energy_, tet_gradient_, tet_blocks_, quadratic_gradient_, quadratic_energy_;
};

}  // namespace tailor
