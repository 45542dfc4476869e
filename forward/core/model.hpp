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
  const Elimination& elimination() const { return elimination_; }
  Elimination& elimination() { return elimination_; }

  // Sums over all terms, in full DOF space.
  double energy(const Vector& x, const Vector& p) const;
  Vector gradient(const Vector& x, const Vector& p) const;
  Vector param_gradient(const Vector& x, const Vector& p) const;
  SparseMatrix mixed(const Vector& x, const Vector& p) const;  // n x |p|
  Vector hessian_times(const Vector& x, const Vector& p, const Vector& w) const;  // exact (d2E/dx2) w
  Vector mixed_transpose_times(const Vector& x, const Vector& p, const Vector& w) const;  // (d2E/dxdp)^T w
  double max_step(const Vector& x, const Vector& dx) const;

 private:
  int num_dofs_;
  std::vector<std::unique_ptr<EnergyTerm>> terms_;
  ParameterLayout parameters_;
  Elimination elimination_;
};

}  // namespace tailor
