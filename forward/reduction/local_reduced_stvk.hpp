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
//
// Evaluation: each group keeps only the lower triangle of its coefficient matrix G_g, packed
// by columns (half the memory of ReducedStvk's), and reads it once per evaluation: one sweep
// gives G w, the cubic part B J_s and the quartic part L J_s of the tangent together
// (evaluate_stvk_polynomial reads G twice). The sweep is bound by memory bandwidth, so this
// halves an evaluation's cost; groups are evaluated in parallel (OpenMP) and summed in group
// order, so the result does not depend on the thread count.
#include <cstddef>
#include <vector>

#include "forward/core/model.hpp"
#include "forward/mesh/mesh.hpp"
#include "forward/reduction/reduced_elastic_model.hpp"

namespace tailor {

class LocalReducedStvk final : public ReducedElasticModel {
 public:
  // model: its elastic terms (ElasticTerm, 2D or 3D) must use StVK; other terms are ignored
  // (loads enter reduced dynamics as projected forces). mesh: the model's mesh (vertex DOFs
  // interleaved). basis: num_dofs x r displacements; an entry counts as nonzero when its
  // magnitude exceeds zero_tolerance. Throws std::invalid_argument on size mismatch, another
  // material or no elastic term.
  // Precomputation: per group, chunks of 256 elements' strain columns (OpenMP) and one BLAS
  // rank-k update each (dsyrk, OpenBLAS's threads); O(elements_g (r_g + P_g)^2) per group.
  LocalReducedStvk(const Model& model, const Mesh& mesh, const Vector& p, const Matrix& basis,
                   double zero_tolerance = 0.0);
  ~LocalReducedStvk() override;

  int size() const override { return r_; }
  void evaluate(const Vector& q, double* energy, Vector* force, Matrix* stiffness) const override;

  int groups() const { return static_cast<int>(groups_.size()); }
  const std::vector<int>& group_columns(int g) const { return groups_[static_cast<std::size_t>(g)].columns; }
  int largest_group() const;  // most columns in one group
  double precomputation_seconds() const { return precomputation_seconds_; }
  double precomputation_cpu_seconds() const { return precomputation_cpu_seconds_; }  // all threads
  std::size_t coefficient_bytes() const;  // the packed coefficients of every group

 private:
  struct Group {
    std::vector<int> columns;
    std::vector<double> lower;  // G_g's lower triangle, column j holding rows j..width-1
  };
  // W_g, dW_g/dq_g, d2W_g/dq_g^2 of one group at its coordinates q (sized, zeroed outputs).
  static void evaluate_group(const Group& group, const Vector& q, double* energy, Vector* force, Matrix* stiffness);
  int r_ = 0;
  std::vector<Group> groups_;
  double precomputation_seconds_ = 0.0, precomputation_cpu_seconds_ = 0.0;
};

}  // namespace tailor
