#pragma once
// Bending limits of the macro-scale interlocking sheet (docs/interlocking.md, "Macro-scale model"):
// a curvature barrier on the single-curvature limits kappa(theta) that native sweeps of bending
// patches measure (strain_boundary.hpp with RigidCellSpec::bending_patch, uniaxial curvature paths:
// z = 1/2 kappa (d.p)^2, d = (cos theta, sin theta)).
//
// Fit: kappa(theta + pi) = kappa(theta) (a cylinder bent along d or -d is the same), so 1 / kappa is
// a Fourier series in 2 theta, 1 / kappa(theta) = a_0 + sum_k (a_k cos 2k theta + b_k sin 2k theta),
// fitted by least squares (residuals reported in kappa; a fit that is not positive everywhere is
// refused). The compliance 1 / kappa rather than kappa: a net's limits peak sharply where its links
// never lock (the square net: 0.249 along the links, 0.620 along the diagonal), and the reciprocal
// of a peak is a shallow dip that few terms fit (at order 6 on the square net: residual 0.0038 at 0
// degrees against 0.021 for a fit of kappa itself, whose error spreads evenly).
//
// Discrete curvature: per interior edge (hinge) of the sheet, the normal curvature across it,
//   kappa_e^2 = 2 (1 - n1 . n2) / l_e^2 = (2 sin(theta_e / 2) / l_e)^2,
// n1, n2 the unit normals of its two triangles, theta_e the dihedral angle, l_e = (A1 + A2) / |e|
// the mean of the two triangles' rest heights over the edge: the linear interpolant of a cylinder
// z = 1/2 kappa (m.p)^2 bent across the edge (m the edge's in-plane unit normal at rest) turns by
// theta_e = kappa l_e there. Its limit is the fit at the edge's own direction, kappa_lim(angle of m),
// a constant per hinge. The margin g_e = 1 - kappa_e^2 / kappa_lim^2 (1 flat, 0 at the limit, either
// sign of bending: the flat nets bend alike up and down) carries IPC's clamped log barrier
// (Li et al. 2020, eq. 6), weighted by the hinge's area (A1 + A2) / 3:
//   E = kappa_b sum_e (A1 + A2) / 3 b(g_e),  b(g) = -(g - g_hat)^2 log(g / g_hat) for g < g_hat,
// +infinity for g <= 0. So the admissible set is the normal-curvature slab |kappa_e| <= kappa_lim at
// every hinge: exact for single curvature across a family of mesh edges (a cylinder along a mesh
// direction), and for other curvatures a bound that depends on the mesh's edge directions (a
// per-triangle curvature tensor would not; see the docs). Exact derivatives: n1 . n2 of the hinge's
// 4 vertices (12 coordinates) by Dual2<12>. DOFs as MacroSheetTerm's: 3 per vertex [length].
#include <vector>

#include "forward/core/energy_term.hpp"
#include "forward/mesh/mesh.hpp"

namespace tailor::interlocking {

struct BendingLimitFit {
  std::vector<double> coefficients;  // a_0, a_1, b_1, ..., a_K, b_K of 1 / kappa  [length]
  int samples = 0;
  double rms_residual = 0.0, max_residual = 0.0;  // [1 / length]
  double min_limit = 0.0;                         // smallest kappa(theta) [1 / length]
  // 1 / kappa_lim at the curvature direction theta [rad] -> [length] (checked positive).
  double compliance(double theta) const;
  // kappa_lim at the curvature direction theta [rad] -> [1 / length].
  double limit(double theta) const;
};

// Least squares of order K to samples (theta [rad], kappa > 0). Throws std::invalid_argument for
// K < 0, a non-positive or non-finite sample, fewer distinct directions (mod pi) than 2K + 1, or a
// fit that is not positive on [0, pi).
BendingLimitFit fit_bending_limits(const std::vector<Eigen::Vector2d>& samples, int order);

struct CurvatureBarrier {
  double stiffness = 1.0;   // kappa_b [energy / area]
  double activation = 0.1;  // g_hat in (0, 1)
};

class BendingLimitTerm final : public EnergyTerm {
 public:
  // `flat`: the rest sheet (2D triangles, counter-clockwise). Throws std::invalid_argument for a
  // bad mesh or barrier.
  BendingLimitTerm(const Mesh& flat, const BendingLimitFit& fit, CurvatureBarrier barrier);
  std::string name() const override { return "sheet_bending_limit"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;
  // The largest fraction of dx before a hinge's margin falls to a fifth of its current value (16
  // samples along the step, then bisection), as MacroSheetTerm::max_step.
  double max_step(const Vector& x, const Vector& dx) const override;

  int num_hinges() const { return static_cast<int>(hinges_.size()); }
  // Per hinge at x: the signed-free normal curvature kappa_e [1 / length], and the margin g_e.
  Eigen::VectorXd curvatures(const Vector& x) const;
  Eigen::VectorXd margins(const Vector& x) const;
  // Per hinge: the rest in-plane normal's angle [rad] and the limit kappa_lim there [1 / length].
  Eigen::VectorXd normal_angles() const;
  Eigen::VectorXd limits() const;

 private:
  struct Hinge {
    int vertices[4];  // edge (0, 1), then the opposite vertex of triangle 1 (2) and of triangle 2 (3)
    int triangles[2][3];  // each triangle's corners as indices into vertices[], in mesh order
    double length = 0.0;  // l_e [length]
    double weight = 0.0;  // (A1 + A2) / 3 [area]
    double limit = 0.0;   // kappa_lim [1 / length]
    double angle = 0.0;   // rest in-plane normal [rad]
  };
  double margin(const Vector& x, const Hinge& h) const;
  std::vector<Hinge> hinges_;
  CurvatureBarrier barrier_;
};

}  // namespace tailor::interlocking
