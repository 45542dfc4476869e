#pragma once
// The exact StVK reduced polynomial (reduced_stvk.hpp) for a basis whose columns are local, as
// domain-decomposed and overlapping-domain bases are: each element's energy depends only on the
// columns that are nonzero on its vertices. Elements are grouped by that column set, every
// group gets its own ReducedStvk over its columns alone, and
//   W(q) = sum_g W_g(q restricted to the columns of g).
// Exact (the same polynomial as one ReducedStvk over the whole basis, tested), but the
// precomputation costs O(sum_g elements_g r_g^4) and an evaluation O(sum_g r_g^4) instead of
// O(mesh r^4) and O(r^4): with k domains of r/k columns each, about k^3 times less. A basis
// without locality gives one group, which is ReducedStvk itself.
#include <memory>
#include <vector>

#include "forward/core/model.hpp"
#include "forward/mesh/mesh.hpp"
#include "forward/reduction/reduced_elastic_model.hpp"

namespace tailor {

class ReducedStvk;

class LocalReducedStvk final : public ReducedElasticModel {
 public:
  // model: its elastic terms (StVK or linear, as ReducedStvk) must split by elements
  // (EnergyTerm::share_by_elements); other terms are ignored. mesh: the model's mesh (vertex
  // DOFs interleaved). basis: num_dofs x r displacements; an entry counts as nonzero when its
  // magnitude exceeds zero_tolerance. Throws std::invalid_argument on size mismatch.
  LocalReducedStvk(const Model& model, const Mesh& mesh, const Vector& p, const Matrix& basis,
                   double zero_tolerance = 0.0);
  ~LocalReducedStvk() override;

  int size() const override { return r_; }
  void evaluate(const Vector& q, double* energy, Vector* force, Matrix* stiffness) const override;

  int groups() const { return static_cast<int>(groups_.size()); }
  const std::vector<int>& group_columns(int g) const { return groups_[static_cast<std::size_t>(g)].columns; }
  int largest_group() const;  // most columns in one group
  double precomputation_seconds() const { return precomputation_seconds_; }

 private:
  struct Group {
    std::vector<int> columns;
    std::unique_ptr<ReducedStvk> polynomial;
  };
  int r_ = 0;
  std::vector<Group> groups_;
  double precomputation_seconds_ = 0.0;
};

}  // namespace tailor
