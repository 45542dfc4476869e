#pragma once
// The MLS shape functions evaluated once at the quadrature points (docs/meshless.md): per
// point its weight, covering nodes, phi_a and grad phi_a. The energy terms read only this.
#include <Eigen/Core>
#include <vector>

#include "forward/core/types.hpp"
#include "forward/meshless/mls_shape_functions.hpp"

namespace tailor {

struct MeshlessQuadrature {
  int num_nodes = 0;
  std::vector<double> weights;        // per point
  std::vector<Eigen::Vector3d> points;
  std::vector<int> begin;             // point q's entries are [begin[q], begin[q+1])
  std::vector<int> nodes;             // per entry: covering node
  std::vector<double> values;         // per entry: phi_a(X_q)
  std::vector<Eigen::Vector3d> gradients;  // per entry: grad phi_a(X_q)
  double max_condition = 0.0;         // largest moment-matrix condition number met

  int num_points() const { return static_cast<int>(weights.size()); }
  int size(int q) const { return begin[static_cast<std::size_t>(q) + 1] - begin[static_cast<std::size_t>(q)]; }
  // F_q = sum_a x_a grad phi_a(X_q)^T for interleaved x (3 per node).
  Eigen::Matrix3d deformation_gradient(const Vector& x, int q) const;
  // sum_a phi_a(X_q) v_a for a per-node scalar field v.
  double interpolate(const Vector& v, int offset, int q) const;
};

// Evaluates `mls` at every point (points: q x 3, weights: q). Any point where the shape
// functions do not exist throws MeshlessPointError naming it (mls_shape_functions.hpp).
MeshlessQuadrature build_meshless_quadrature(const MlsShapeFunctions& mls, const Eigen::MatrixXd& points,
                                             const Eigen::VectorXd& weights);

// Consistent nodal forces of a force density g(X) sampled at points with weights (a surface
// traction with surface weights, a body force with volume weights): f_a = sum_s w_s phi_a(X_s)
// g_s (interleaved, size 3n). densities: s x 3.
Vector meshless_point_forces(const MlsShapeFunctions& mls, const Eigen::MatrixXd& points,
                             const Eigen::VectorXd& weights, const Eigen::MatrixXd& densities);

// Consistent mass matrix (3n x 3n, interleaved like x) of a uniform density rho:
// M_(3a+k)(3b+k) = rho sum_q w_q phi_a(X_q) phi_b(X_q). The sum of a component's entries is
// rho times the quadrature's volume (partition of unity).
SparseMatrix meshless_mass_matrix(const MeshlessQuadrature& quadrature, double density);

}  // namespace tailor
