#pragma once
// Model: a sum of energy terms over one DOF layout, plus constraints x = x0 + S y and the
// layout of the parameter vector p. A scene adds only the terms it needs.
#include <memory>
#include <string>
#include <vector>

#include "forward/core/elimination.hpp"
#include "forward/core/energy_term.hpp"

namespace tailor {

// Named blocks of the flat parameter vector p ("youngs_modulus", "poisson_ratio", ...).
class ParameterLayout {
 public:
  struct Block {
    std::string name;
    int offset;
    int size;
  };
  // Appends a block and returns its offset. Throws if the name is taken.
  int add(const std::string& name, int size);
  // Throws std::out_of_range naming the block when absent.
  const Block& at(const std::string& name) const;
  bool contains(const std::string& name) const;
  int size() const { return size_; }
  const std::vector<Block>& blocks() const { return blocks_; }

 private:
  std::vector<Block> blocks_;
  int size_ = 0;
};

class Model {
 public:
  explicit Model(int num_dofs);

  int num_dofs() const { return num_dofs_; }

  // Terms are owned by the model; the returned reference stays valid for its lifetime.
  template <class Term>
  Term& add(std::unique_ptr<Term> term) {
    Term& ref = *term;
    terms_.push_back(std::move(term));
    return ref;
  }
  const std::vector<std::unique_ptr<EnergyTerm>>& terms() const { return terms_; }

  ParameterLayout& parameter_layout() { return parameters_; }
  const ParameterLayout& parameter_layout() const { return parameters_; }

  void set_elimination(Elimination elimination);

  // Parameters that prescribe constrained DOFs (handles moved by the design):
  //   x = x0 + D p + S y,
  // D (num_dofs x |p|) with entries only in rows the elimination fixes. Set after the
  // elimination and the parameter layout. Throws std::invalid_argument otherwise.
  void set_prescribed_parameters(SparseMatrix prescribed);
  // Convenience: a new parameter block `name` of |dofs| entries, each the displacement of one
  // fixed DOF (D(dofs[k], offset + k) = 1); returns the block's offset.
  int add_prescribed_displacements(const std::string& name, const std::vector<int>& dofs);
  bool has_prescribed_parameters() const { return prescribed_.nonZeros() > 0; }
  const SparseMatrix& prescribed_parameters() const { return prescribed_; }
  // The full state x = x0 + D p + S y.
  Vector state(const Vector& y, const Vector& p) const;
  const Elimination& elimination() const { return elimination_; }
  Elimination& elimination() { return elimination_; }

  // Sums over all terms, in full DOF space.
  double energy(const Vector& x, const Vector& p) const;
  Vector gradient(const Vector& x, const Vector& p) const;
  Vector param_gradient(const Vector& x, const Vector& p) const;
  SparseMatrix mixed(const Vector& x, const Vector& p) const;  // n x |p|
  Vector hessian_times(const Vector& x, const Vector& p, const Vector& w) const;  // exact (d2E/dx2) w
  // The terms' low-rank Hessian parts (see LowRankHessian), concatenated.
  LowRankHessian low_rank_hessian(const Vector& x, const Vector& p, HessianMode mode = HessianMode::exact) const;
  Vector mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w) const;  // (d2E/dxdp)^T w
  double max_step(const Vector& x, const Vector& dx) const;
  // True when every term's Hessian is independent of x (EnergyTerm::hessian_is_constant).
  bool hessian_is_constant() const;
  // The terms' hessian_revision() values, in term order: a constant Hessian at fixed p is
  // unchanged while these are.
  std::vector<std::uint64_t> hessian_revisions() const;

 private:
  int num_dofs_;
  std::vector<std::unique_ptr<EnergyTerm>> terms_;
  ParameterLayout parameters_;
  Elimination elimination_;
  SparseMatrix prescribed_;
  std::vector<Triplet> prescribed_triplets_;  // accumulated by add_prescribed_displacements
};

}  // namespace tailor
