#pragma once
// Periodic single curvature (docs/interlocking.md, "Bending: periodic single curvature"): the
// flat cell's periodicity T_j = T_i + F t, w_j = w_i replaced by the screw motions of a cylinder.
//
// A sheet bent to curvature kappa along the in-plane direction d = (cos t, sin t) lies on the
// circular cylinder whose axis is parallel to e = (-sin t, cos t, 0) through the centre
// c = T_anchor + e_z / kappa (the cylinder touches the plane z = T_anchor,z at the anchor's rest
// centre; kappa > 0 bends the sheet up, towards +z). A lattice shift t = L k (arc length u = d.t
// along the sheet, v = e.t along the axis) maps a master to its image by the screw motion
//   T_j = Q_k (T_i - c) + c + v e,   R(w_j) = Q_k R(w_i),   Q_k = exp(kappa u [a]),  a = d x e_z,
// a group homomorphism of the lattice (the screws share their axis), so every periodic pair class
// is still one master-image pair and the cell's barrier is the energy of one cell. At kappa = 0
// it is the flat cell's map at F = I exactly (the series below). T_j is linear in T_i, but
// w_j = log(Q_k exp(w_i)) is nonlinear in the master's rotation vector: the images' DOFs are a
// nonlinear map x(y, kappa) of the free master DOFs, outside the linear Elimination of
// PeriodicRigidCell, and its Jacobian and second derivatives enter the reduced gradient and
// Hessian:
//   E(y) = B(x(y)),  dE/dy = J^T g,  d2E/dy2 = J^T H J + sum_r g_r d2x_r/dy2   (g = dB/dx).
// Only the images' rotation rows have second derivatives. They come from the inverse function
// theorem on R(w_j) = P(z) := Q(kappa) R(w_i), z = (w_i, kappa): with [J_m] = dR/dw_j,m R^T (the
// rotation vector's spatial Jacobian, regular for |w_j| < 2 pi, so also at |w_j| = pi where the
// log's branch formulas degenerate),
//   dw_j/dz_a = J^-1 vee(dP/dz_a R^T),
//   d2w_j/dz_a dz_b = J^-1 vee((d2P/dz_a dz_b - sum_mn d2R/dw_m dw_n A_ma A_nb) R^T),   A = dw_j/dz,
// exact at every angle (rigid/rotation.hpp's R(w) derivatives carry the small-angle series).
// The image's rotation vector is the representative of log(Q R(w_i)) nearest to w_i + kappa u a.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "forward/core/energy_term.hpp"
#include "forward/interlocking/periodic_cell.hpp"

namespace tailor::interlocking {

// w_j = log(Q R(w_master)) with its derivatives in z = (w_master, kappa) given Q(kappa) and its
// first and second kappa-derivatives (dQ, d2Q). Rotation vectors [rad].
struct ImageRotation {
  Eigen::Vector3d w;                        // w_j
  Eigen::Matrix<double, 3, 4> jacobian;     // dw_j / dz
  std::array<Eigen::Matrix4d, 3> hessian;   // d2 w_j,m / dz dz (symmetric)
};
ImageRotation image_rotation(const Eigen::Matrix3d& Q, const Eigen::Matrix3d& dQ, const Eigen::Matrix3d& d2Q,
                             const Eigen::Vector3d& w_master, const Eigen::Vector3d& near);

// The screw motion of one lattice shift on the cylinder (see above): T_j = Q T_i + b, with the
// first and second derivatives of Q and b in kappa [1/length].
struct CylinderScrew {
  Eigen::Matrix3d Q, dQ, d2Q;
  Eigen::Vector3d b, db;
  Eigen::Vector3d axis_rate;  // u a: Q = exp(kappa [u a])
};
CylinderScrew cylinder_screw(double kappa, double angle, const Eigen::Vector3d& anchor, const Eigen::Vector2d& shift);

// A periodic cell (not a bending patch) bent to single curvature along `angle` [rad]. Holds a
// reference to `cell`, which must outlive it. y: the cell's free DOFs (PeriodicRigidCell::basis
// columns: every master's six, the anchor's translation held at its rest value).
class SingleCurvatureCell {
 public:
  SingleCurvatureCell(const PeriodicRigidCell& cell, double angle);

  const PeriodicRigidCell& cell() const { return *cell_; }
  double angle() const { return angle_; }
  int num_free() const { return cell_->num_free(); }
  // The macro argument of reports: F = I + kappa d d^T, so that sym(F) - I is the curvature tensor.
  Eigen::Matrix2d deformation(double kappa) const;

  // x(y, kappa): masters from y, images by their screw motions (6 per body, masters first).
  Vector full_state(const Vector& y, double kappa) const;

  // x with dx/dy (sparse, 6 bodies x free), dx/dkappa, and what the second derivatives need.
  struct MapDerivatives {
    Vector x;
    SparseMatrix jacobian;
    Vector curvature_derivative;               // dx/dkappa at fixed y
    std::vector<ImageRotation> rotations;      // per image (body - N)
    std::vector<Eigen::Matrix3d> rotation_rate;  // per image: dQ/dkappa
  };
  MapDerivatives map(const Vector& y, double kappa) const;

  // B(x(y, kappa)) with its reduced derivatives: gradient J^T g, the dense reduced Hessian
  // (exact: J^T H J + sum_r g_r d2x_r/dy2; projected: J^T H+ J with H+ the per-pair PSD
  // projection, a Gauss-Newton matrix for Newton steps: projecting the exact sum instead leaves
  // near-zero eigenvalues where g has components, and Newton steps of length ~|g|/mu), and
  // (mixed, exact only) d/dkappa of the gradient, J^T H dx/dkappa + (dJ/dkappa)^T g. Energy
  // +infinity (and nothing else) for an intersecting state.
  struct Reduced {
    double energy = 0.0;
    Vector x, full_gradient, gradient, mixed, curvature_derivative;
    double curvature_gradient = 0.0;  // dE/dkappa = g . dx/dkappa
    Matrix hessian;
    SparseMatrix full_hessian;
    SparseMatrix jacobian;
  };
  Reduced reduce(const Vector& y, double kappa, bool hessian, HessianMode mode = HessianMode::exact) const;

  // The masters carried from the cylinder of kappa_old to that of kappa_new (a ramp's predictor):
  // each free master's centre keeps its arc coordinates (u along d, v along e, height h over the
  // cylinder) and turns with the cylinder's tangent frame.
  Vector bend_masters(const Vector& y, double kappa_old, double kappa_new) const;

 private:
  const PeriodicRigidCell* cell_;
  double angle_;
  std::vector<int> column_;  // y column of each master DOF (6 N; -1: held)
  std::vector<CylinderScrew> screws(double kappa) const;
};

// The contact energy of a single-curvature cell as an EnergyTerm over y with p = (kappa): the
// nonlinear periodic constraint written as a term, so that check_energy_term covers it (value,
// gradient, Hessian, dE/dkappa and the mixed block).
class SingleCurvatureContactTerm final : public EnergyTerm {
 public:
  explicit SingleCurvatureContactTerm(const SingleCurvatureCell& cell) : cell_(&cell) {}
  std::string name() const override { return "single_curvature_contact"; }
  void evaluate(const Vector& y, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;
  void add_param_gradient(const Vector& y, const Vector& p, Vector& gradient_p) const override;
  void add_mixed(const Vector& y, const Vector& p, Triplets& mixed) const override;

 private:
  const SingleCurvatureCell* cell_;
};

}  // namespace tailor::interlocking
