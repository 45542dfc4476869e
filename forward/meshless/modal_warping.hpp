#pragma once
// Modal warping (Choi & Ko, "Modal warping: real-time simulation of large rotational
// deformation and manipulation", IEEE TVCG 2005) on meshless modes, with Rayleigh-damped modal
// dynamics (docs/meshless.md, "Modal warping").
//
// Linear modal displacement at an evaluation point X_i (a node, a surface sample):
//   u_L(X_i) = L_i q,  L_i = sum_b phi_b(X_i) Phi_b   (3 x r; Phi_b: node b's rows of the modes),
// its rotation vector (half the curl, from the MLS gradients):
//   w_i = 1/2 curl u_L(X_i) = C_i q,  C_i = 1/2 sum_b [grad phi_b(X_i)]_x Phi_b,
// and the warped displacement (Choi & Ko eq. 11, the rotation accumulated as the linear
// displacement grows from 0 to u_L):
//   u(X_i) = W(w_i) u_L(X_i),  W(w) = int_0^1 exp(s [w]_x) ds
//          = I + (1 - cos t) / t^2 [w]_x + (t - sin t) / t^3 [w]_x^2,   t = |w|.
// A linearized rigid rotation u_L = theta e x X is warped into the exact rotation
// (exp(theta [e]_x) - I) X, for any angle.
//
// Dynamics per mass-normalized mode j (Phi^T M Phi = I, eigenvalue lambda_j = omega_j^2):
//   q_j'' + (alpha + beta lambda_j) q_j' + lambda_j q_j = f_j,
// Rayleigh damping C = alpha M + beta K, damping ratio zeta_j = alpha / (2 omega_j) + beta omega_j / 2.
// The step is exact for a force constant over the step (the 2 x 2 matrix exponential per mode),
// so it is stable and undamped numerically at any step. A force f applied at X_i is rotated into
// the local frame, f_q = L_i^T R_i^T f with R_i = exp([w_i]_x) (Choi & Ko section 4.2).
//
// Handles (position and rotation, for manipulation) are stiff penalty springs in the reduced
// coordinates: a handle holds evaluation points i at warped displacements d_i and, for a
// rotation handle, their rotation vectors at w_t. In the warped model both are linear in q once
// the rotation is known: w_i = C_i q = w_t and u_i = W(w_t) L_i q = d_i, i.e. L_i q = W(w_t)^-1 d_i.
// (A position-only handle takes W at the current w_i = C_i q, updated every step: a fixed point
// the damped dynamics settle into.) The penalty k/2 sum |G q - g|^2 (rotation rows weighted by
// the handle's squared size) turns the modal stiffness into K' = Lambda + k G^T G, which couples
// the modes; its eigenvectors V (K' = V Lambda' V^T, V^T V = I) decouple them again, with the
// Rayleigh damping alpha + beta lambda'_j of K' per new mode, so the step stays exact for a force
// constant over the step and the stiff springs stay stable at any step. The handle force
// k G^T g enters like an applied modal force. Rigid modes (lambda = 0) are allowed when the
// handles hold them (K' positive definite); a zero-stiffness mode left free is refused.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "forward/core/types.hpp"
#include "forward/meshless/mls_shape_functions.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor {

// W(w) = int_0^1 exp(s [w]_x) ds and the rotation exp([w]_x) (Rodrigues), accurate near w = 0.
Eigen::Matrix3d warping_matrix(const Eigen::Vector3d& w);
Eigen::Matrix3d rotation_matrix(const Eigen::Vector3d& w);

// The per-point operators of `modes` (3n x r, interleaved node coefficients) at points (m x 3).
struct ModalWarpingOperators {
  Eigen::MatrixXd displacement;  // 3m x r: rows 3i..3i+2 are L_i
  Eigen::MatrixXd rotation;      // 3m x r: rows 3i..3i+2 are C_i
  int num_points() const { return static_cast<int>(displacement.rows() / 3); }
};
ModalWarpingOperators modal_warping_operators(const MlsShapeFunctions& mls, const Eigen::MatrixXd& modes,
                                              const Eigen::MatrixXd& points);

// The same operators for P1 (linear tetrahedron) modes (3n x r, interleaved vertex values) at
// the mesh's vertices: L_i = Phi_i (vertex i's rows), and C_i the volume-weighted average over
// the tets around vertex i of their constant 1/2 curl, 1/2 sum_a [grad N_a]_x Phi_a (the tet
// gradient operator; Choi & Ko section 3.2 average the per-element rotations to the nodes the
// same way). A linear field (a linearized rigid rotation among them) gives every vertex its
// exact curl. std::invalid_argument for a mesh that is not tetrahedral or for bad sizes.
ModalWarpingOperators fem_modal_warping_operators(const Mesh& mesh, const Eigen::MatrixXd& modes);

struct ModalRayleighDamping {
  double alpha = 0.0;  // mass-proportional [1/s]
  double beta = 0.0;   // stiffness-proportional [s]
  double ratio(double eigenvalue) const;  // zeta for lambda = omega^2
};

// A handle on evaluation points of the operators (see above).
struct ModalHandle {
  std::vector<int> points;                  // rows of the operators held
  Eigen::MatrixXd displacements;            // points.size() x 3: target warped displacements d_i
  std::optional<Eigen::Vector3d> rotation;  // target rotation vector w_t (rotation handles)
  double rotation_weight = 1.0;             // [length^2] of the rotation rows (the handle's size^2)
};

class WarpedModalSimulator {
 public:
  // eigenvalues: lambda_j >= 0 of the mass-normalized modes behind `operators`; time_step > 0;
  // handle_stiffness k [1/s^2] (> 0 with handles). std::invalid_argument for bad sizes, a handle
  // point out of range, or a mode of zero stiffness that no handle holds.
  WarpedModalSimulator(ModalWarpingOperators operators, Eigen::VectorXd eigenvalues, ModalRayleighDamping damping,
                       double time_step, std::vector<ModalHandle> handles = {}, double handle_stiffness = 0.0);

  int num_modes() const { return static_cast<int>(q_.size()); }
  const Eigen::VectorXd& amplitudes() const { return q_; }
  const Eigen::VectorXd& velocities() const { return v_; }
  void set_state(const Eigen::VectorXd& q, const Eigen::VectorXd& v);

  // Modal force of a force f at point i in the current configuration: L_i^T R_i^T f.
  Eigen::VectorXd modal_force(int point, const Eigen::Vector3d& force) const;
  // Modal force of forces at every point (3m, interleaved): sum_i L_i^T R_i^T f_i.
  Eigen::VectorXd modal_force(const Eigen::VectorXd& forces) const;
  // One step with the modal force (and the handles' force) held constant over it.
  void step(const Eigen::VectorXd& modal_force);
  // Moves handle h to new targets (same points): interactive manipulation.
  void move_handle(int h, const Eigen::MatrixXd& displacements, const std::optional<Eigen::Vector3d>& rotation);
  const std::vector<ModalHandle>& handles() const { return handles_; }
  // Warped (or, with warp = false, linear) displacements at all points (3m), into `u`.
  void displacements(Eigen::VectorXd& u, bool warp = true) const;

 private:
  Eigen::VectorXd handle_force() const;  // k G^T g at the current state
  ModalWarpingOperators operators_;
  Eigen::VectorXd lambda_, q_, v_;
  std::vector<ModalHandle> handles_;
  double stiffness_ = 0.0;
  Eigen::MatrixXd basis_;  // V: the modes of K' (empty without handles)
  std::vector<Eigen::Matrix2d> transition_;  // per mode: exp(A h)
  std::vector<Eigen::Vector2d> forcing_;     // per mode: response to a unit constant force
};

}  // namespace tailor
