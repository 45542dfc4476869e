#pragma once
// TargetPositions: match the positions (or displacements) of selected vertices.
//
//   J(x) = 1/2 sum_{i} w_i ||x_{v_i} - t_i||^2,
//
// v_i the selected vertices, t_i their targets, w_i >= 0 their weights (1 by default).
// Target displacements u_i (J = 1/2 sum w_i ||(x_{v_i} - X_{v_i}) - u_i||^2, X the rest
// positions) are the same objective with t_i = X_{v_i} + u_i; displacements() builds it.
// J does not depend on p. Least-squares form: r_{i,k} = sqrt(w_i) (x_{v_i,k} - t_{i,k}),
// ordered vertex by vertex.
#include <vector>

#include "forward/mesh/mesh.hpp"
#include "objectives/objective.hpp"

namespace tailor {

class TargetPositions final : public Objective {
 public:
  // `targets`: one row per selected vertex (|vertices| x dim). `weights`: one per selected
  // vertex, or empty for all ones. Throws std::invalid_argument on bad sizes, negative or
  // duplicate vertex indices, non-finite targets or negative / non-finite weights.
  TargetPositions(int dim, std::vector<int> vertices, Matrix targets, Vector weights = {});

  // Target displacements from the mesh's rest positions: t_i = X_{v_i} + displacements.row(i).
  // Also checks that the vertices exist in the mesh.
  static TargetPositions displacements(const Mesh& mesh, std::vector<int> vertices, const Matrix& displacements,
                                       Vector weights = {});

  std::string name() const override { return "target_positions"; }
  double value(const Vector& x, const Vector& p) const override;
  void add_gradient_x(const Vector& x, const Vector& p, Vector& gx) const override;
  bool has_second_derivatives() const override { return true; }
  void add_hessian_times(const Vector& x, const Vector& p, const Vector& dx, const Vector& dp, Vector& out_x,
                         Vector& out_p) const override;

  bool is_least_squares() const override { return true; }
  int num_residuals() const override { return dim_ * static_cast<int>(vertices_.size()); }
  void residuals(const Vector& x, const Vector& p, Vector& r, SparseMatrix* dr_dx, SparseMatrix* dr_dp) const override;

  const std::vector<int>& vertices() const { return vertices_; }
  const Matrix& targets() const { return targets_; }  // positions, also for displacements()
  const Vector& weights() const { return weights_; }

 private:
  void check_state(const Vector& x) const;
  int dim_;
  std::vector<int> vertices_;
  Matrix targets_;
  Vector weights_;
};

}  // namespace tailor
