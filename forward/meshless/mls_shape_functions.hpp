#pragma once
// Moving-least-squares (element-free Galerkin) shape functions in 3D (docs/meshless.md, "MLS").
//
// With a polynomial basis p (linear: m = 4 terms; quadratic: m = 10), compact weights
// w_a(X) = W(|X - X_a| / R_a) and the moment matrix A(X) = sum_a w_a(X) p(X_a) p(X_a)^T,
//   phi_a(X) = p(X)^T A(X)^-1 p(X_a) w_a(X)
// (Lancaster & Salkauskas 1981; Belytschko, Lu & Gu 1994). The basis is shifted to the
// evaluation point and scaled by the largest covering support radius, p((Y - X) / s), which
// leaves phi unchanged and keeps A well scaled. Gradients, with gamma = A^-1 p(X):
//   d phi_a / dX_k = w_a p_a^T dgamma_k + (dw_a / dX_k) p_a^T gamma,
//   dgamma_k = A^-1 (dp(X) / dX_k - A_k gamma),  A_k = sum_b (dw_b / dX_k) p_b p_b^T.
// W is the C2 cubic spline: 2/3 - 4r^2 + 4r^3 on [0, 1/2], 4/3 - 4r + 4r^2 - 4r^3/3 on
// [1/2, 1], 0 beyond. R_a = support_factor * (node spacing at a).
//
// A point covered by fewer than m nodes, or whose moment matrix has a condition number
// (largest over smallest eigenvalue) above max_condition, is refused with a MeshlessPointError
// naming its coordinates; it is never used silently.
#include <Eigen/Core>
#include <stdexcept>
#include <string>
#include <vector>

#include "forward/core/types.hpp"

namespace tailor {

enum class MlsBasis { linear, quadratic };

struct MlsOptions {
  MlsBasis basis = MlsBasis::linear;
  double support_factor = 2.0;  // R_a = support_factor * spacing_a
  double max_condition = 1e8;   // of the scaled moment matrix
};

// A point where the shape functions do not exist (too few covering nodes, ill-conditioned
// moment matrix): what() names the point's coordinates and the reason.
class MeshlessPointError : public std::runtime_error {
 public:
  MeshlessPointError(const std::string& message, const Eigen::Vector3d& point)
      : std::runtime_error(message), point_(point) {}
  const Eigen::Vector3d& point() const { return point_; }

 private:
  Eigen::Vector3d point_;
};

// The shape functions with a non-zero weight at one point.
struct MlsValues {
  std::vector<int> nodes;     // covering nodes, increasing
  Eigen::VectorXd values;     // phi_a
  Eigen::MatrixXd gradients;  // row a: grad phi_a^T (nodes.size() x 3)
  double condition = 0.0;     // of the scaled moment matrix
};

class MlsShapeFunctions {
 public:
  // nodes: n x 3 rest positions; spacing: per node, > 0. std::invalid_argument on bad input.
  MlsShapeFunctions(Eigen::MatrixXd nodes, Eigen::VectorXd spacing, MlsOptions options = {});

  int num_nodes() const { return static_cast<int>(nodes_.rows()); }
  int basis_size() const { return options_.basis == MlsBasis::linear ? 4 : 10; }
  const Eigen::MatrixXd& nodes() const { return nodes_; }
  double support_radius(int a) const { return radius_[a]; }
  const MlsOptions& options() const { return options_; }

  // Values and gradients at X; MeshlessPointError where they do not exist (see above).
  MlsValues evaluate(const Eigen::Vector3d& X) const;
  // The nodes whose support contains X (|X - X_a| < R_a), increasing.
  std::vector<int> covering_nodes(const Eigen::Vector3d& X) const;
  // sum_a phi_a(X) x_a for interleaved nodal coefficients x (size 3n).
  Eigen::Vector3d interpolate(const Vector& x, const Eigen::Vector3d& X) const;

  // The cubic spline W(r) and W'(r) / r (finite at r = 0).
  static double weight(double r, double* derivative_over_r);

 private:
  Eigen::MatrixXd nodes_;
  Eigen::VectorXd radius_;
  MlsOptions options_;
  // Uniform bucket grid of cell >= the largest radius, for the covering search.
  Eigen::Vector3d grid_lo_;
  double grid_cell_ = 1.0;
  Eigen::Vector3i grid_size_;
  std::vector<int> bucket_begin_, bucket_nodes_;
};

}  // namespace tailor
