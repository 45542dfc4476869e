#pragma once
// MaterialSmoothness: penalise jumps of a per-element material field between face-adjacent
// elements (a discrete Dirichlet energy),
//
//   J(p) = alpha/2 s^T L s = alpha/2 sum_{(e,f) adjacent} w_ef (s_e - s_f)^2,
//
// with q = p[offset .. offset + num_elements) the field (e.g. Young's moduli), s = q or
// s = log(q) (jumps measured as ratios, natural for moduli that span decades; needs q > 0),
// and L the weighted graph Laplacian of element_adjacency(mesh):
//   L_ee = sum_f w_ef,  L_ef = -w_ef for adjacent e != f.
// Weights:
//   unit:                w_ef = 1.
//   facet_over_distance: w_ef = |F_ef| / |c_e - c_f|, |F_ef| the rest measure of the shared
//                        facet (area in 3D, length in 2D) and c the rest centroids. This is
//                        the two-point flux approximation of finite volumes, so s^T L s
//                        approximates the integral of |grad s|^2 over the body (exactly so on
//                        orthogonal meshes) and does not change with mesh refinement the way
//                        unit weights do.
// J does not depend on x. Least-squares form: one residual per adjacent pair,
// r_ef = sqrt(alpha w_ef) (s_e - s_f), in the order of element_adjacency.
#include "forward/mesh/mesh.hpp"
#include "forward/mesh/element_laplacian.hpp"
#include "objectives/objective.hpp"

namespace tailor {


struct MaterialSmoothnessOptions {
  AdjacencyWeighting weighting = AdjacencyWeighting::unit;
  bool logarithmic = false;  // act on s = log(q) instead of q
};

class MaterialSmoothness final : public Objective {
 public:
  // Throws std::invalid_argument when the mesh has no elements or is not 2D / 3D simplicial,
  // offset < 0, alpha < 0 or non-finite, or (facet_over_distance) two adjacent elements have
  // coincident centroids or a degenerate shared facet.
  MaterialSmoothness(const Mesh& mesh, int offset, double alpha, MaterialSmoothnessOptions options = {});

  // The num_elements x num_elements Laplacian L defined above (symmetric, rows sum to zero,
  // positive semidefinite; its null space is the constants on each connected component).
  static SparseMatrix laplacian(const Mesh& mesh, AdjacencyWeighting weighting = AdjacencyWeighting::unit);
  // The adjacent pairs (element_adjacency) and their weights w_ef, in the same order.
  static Vector adjacency_weights(const Mesh& mesh, const Eigen::MatrixXi& pairs, AdjacencyWeighting weighting);

  std::string name() const override { return options_.logarithmic ? "material_smoothness(log)" : "material_smoothness"; }
  double value(const Vector& x, const Vector& p) const override;
  void add_gradient_x(const Vector& x, const Vector& p, Vector& gx) const override;
  void add_gradient_p(const Vector& x, const Vector& p, Vector& gp) const override;
  bool has_second_derivatives() const override { return true; }
  void add_hessian_times(const Vector& x, const Vector& p, const Vector& dx, const Vector& dp, Vector& out_x,
                         Vector& out_p) const override;

  bool is_least_squares() const override { return true; }
  int num_residuals() const override { return static_cast<int>(pairs_.rows()); }
  void residuals(const Vector& x, const Vector& p, Vector& r, SparseMatrix* dr_dx, SparseMatrix* dr_dp) const override;

  const SparseMatrix& matrix() const { return laplacian_; }

 private:
  Vector field(const Vector& p) const;  // s (throws std::domain_error for q <= 0 in log mode)
  int offset_, size_;
  double alpha_;
  MaterialSmoothnessOptions options_;
  Eigen::MatrixXi pairs_;
  Vector weights_;
  SparseMatrix laplacian_;
};

}  // namespace tailor
