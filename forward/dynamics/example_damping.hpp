#pragma once
// Example-based damping (Xu & Barbic, "Example-based damping design", SIGGRAPH 2017;
// docs/methods.md section 6) as a dissipation potential on top of Rayleigh damping C = aM + bK.
//
// Examples. U = [u_1 .. u_r] (n x r, displacement fields) M-orthonormal: U^T M U = I, with M
// the mass at set-up; W = M U. A velocity splits M-orthogonally into v = U qd + v_perp,
// qd = W^T v (the example velocities) and W^T v_perp = 0; P = U W^T is the M-orthogonal
// projector on the examples.
//
// Decomposition. In these coordinates the Rayleigh dissipation is
//   v^T C v = qd^T A qd + 2 qd^T U^T C v_perp + v_perp^T C v_perp,     A = U^T C U,
// with a coupling term unless the examples are eigenmodes (then C U = M U diag(a + b lambda)
// and A is diagonal, the coupling zero). Scaling the example part of the damping force by
// gamma_i while leaving the rest unchanged is made precise as
//   C^(gamma) = T^T C T + W Delta W^T,   T = I + U (kappa - I) W^T,
//   kappa_i = 2 gamma_i / (1 + gamma_i),  Delta = diag((gamma_i - kappa_i^2) A_ii).
// T rescales the example velocities by kappa_i
// and leaves v_perp unchanged; T^T C T is the Rayleigh dissipation of the rescaled velocity.
// Properties, for every gamma >= 0:
//  - symmetric positive semidefinite: T^T C T is a congruence of C, and Delta >= 0 because
//    kappa^2 = 4 gamma^2 / (1 + gamma)^2 <= gamma  <=>  (1 - gamma)^2 >= 0 (positive definite
//    for gamma > 0 when C is);
//  - all gamma = 1 gives kappa = 1, T = I, Delta = 0: exactly C;
//  - motion purely along example i (v = u_i) dissipates u_i^T C^ u_i = kappa_i^2 A_ii +
//    (gamma_i - kappa_i^2) A_ii = gamma_i A_ii: gamma_i times Rayleigh's;
//  - couplings: between example i and the rest kappa_i times Rayleigh's, between examples i
//    and j kappa_i kappa_j times; with modes as examples there is none and
//    C^ = C + sum_i (gamma_i - 1) A_ii w_i w_i^T, the paper's force
//    f^ = sum gamma_i f^i + (C v - sum f^i) with f^i = w_i u_i^T C v.
// The coupling factor kappa (rather than sqrt(gamma), the largest factor that keeps the
// example/rest 2x2 blocks semidefinite) keeps C^ smooth in gamma at gamma = 0, where the
// inverse design's bounds put it. kappa saturates at 2 for strong damping; the diagonal
// carries the rest.
//
// Potential. D(v) = D_R(T v) + sum_i (gamma_i - kappa_i^2) D_R(u_i) qd_i^2, D_R Rayleigh's
// dissipation (D_R(u_i) = A_ii / 2). Its Hessian is C on Rayleigh's sparse pattern plus the
// rank-2r part [W Z] G [W Z]^T, Z = C U, G = [[E A E + Delta, E], [E, 0]], E = kappa - I,
// reported through add_dissipation_low_rank_hessian (never an n x n dense matrix).
//
// Nonlinear damping. gamma_i = s_i(chi_i), s_i a monotone cubic (MonotoneCubic) of the
// amplitude of the motion along example i,
//   chi_i = sqrt(a_i^2 (q_i^2 + (qd_i / omega_i)^2) + eps^2) - eps,  q_i = w_i^T (x - X), qd_i = w_i^T v,
// omega_i = sqrt(u_i^T K u_i) the example's frequency (Rayleigh quotient; the eigenfrequency
// for modes), a_i = max |u_i| so that chi_i is the largest nodal displacement [length] the
// example reaches in free oscillation, eps [length] a smoothing that makes chi differentiable
// at rest. For a harmonic oscillation along example i chi_i is constant over the cycle, so
// s_i(A) is the damping scale of an oscillation of amplitude A (the instantaneous |q_i|
// would sweep through 0 where the velocity, hence the dissipation, is largest). gamma is
// lagged: evaluated at the state (x_n, v_n) at the start of each step (set_step_start), so
// each step's potential stays convex in x_{n+1} and its derivatives in (x_n, v_n) are those of
// chi (amplitude_gradient). One knot per example gives a constant (linear) scale.
//
// Rotations. Examples live in the rest frame and do not follow rotations: a finite rigid
// rotation of the body changes q and qd (a bending example rotated by 90 degrees about the
// beam axis is seen as the other bending example) and the damping directions W stay fixed.
// Infinitesimal rigid motions are M-orthogonal to deformation examples and get Rayleigh's
// damping unchanged. Use it for bodies that vibrate about a fixed rest frame (clamped plates,
// leaves), as in the paper's examples.
//
// The examples, their frequencies and W are fixed at set-up (they are not differentiated when
// density or moduli are designed; A_ii = u_i^T C(p) u_i is). add_dissipation_mixed is the
// default column-by-column one (O(n^2)); the adjoint uses the transpose products.
//
// Parameters: those of the base Rayleigh damping, and the control values of all curves in
// one block (curve_offset; example i's values follow example i-1's).
#include <memory>
#include <vector>

#include "forward/dynamics/monotone_spline.hpp"
#include "forward/dynamics/rayleigh_damping.hpp"

namespace tailor {

struct DampingCurve {
  Vector knots = Vector::Zero(1);  // amplitudes chi [length], increasing; one knot = constant scale
};

class ExampleDamping final : public DampingTerm {
 public:
  // base: Rayleigh damping (owned); examples: n x r, M-orthonormal in `mass` (set-up mass);
  // frequencies: omega_i [rad/time]; rest: X (full DOFs); curves: one per example.
  ExampleDamping(std::unique_ptr<RayleighDamping> base, const SparseMatrix& mass, Matrix examples,
                 Vector frequencies, Vector rest, std::vector<DampingCurve> curves, int curve_offset,
                 double amplitude_smoothing = 1e-8);

  std::string name() const override { return "example_damping"; }
  void evaluate_dissipation(const Vector& v, const Vector& p, const EnergyRequest& request) const override;
  void dissipation_pattern(HessianPattern& pattern) const override { base_->dissipation_pattern(pattern); }
  void add_dissipation_param_gradient(const Vector& v, const Vector& p, Vector& gradient_p) const override;
  void add_dissipation_mixed_transpose_times(const Vector& v, const Vector& p, const Vector& w,
                                             Vector& gradient_p) const override;
  void add_dissipation_low_rank_hessian(const Vector& v, const Vector& p,
                                        LowRankHessian& update) const override;
  void set_step_start(const Vector& x, const Vector& v) override;
  void add_step_start_transpose_times(const Vector& x, const Vector& p, const Vector& w, Vector& x_start_bar,
                                      Vector& v_start_bar) const override;

  int num_examples() const { return static_cast<int>(examples_.cols()); }
  int curve_offset() const { return curve_offset_; }
  int num_curve_parameters() const { return num_controls_; }
  int curve_begin(int i) const { return curve_begin_[i]; }  // offset of example i's values in the block
  const Matrix& examples() const { return examples_; }
  const Matrix& mass_examples() const { return mass_examples_; }  // W = M U
  const Vector& frequencies() const { return frequencies_; }
  const RayleighDamping& base() const { return *base_; }

  // chi_i(x, v) [length] and, when asked, d chi_i / dx and d chi_i / dv.
  double amplitude(int i, const Vector& x, const Vector& v, Vector* gradient_x = nullptr,
                   Vector* gradient_v = nullptr) const;
  // The lagged amplitudes (set by set_step_start; zero until then) and setting them directly.
  const Vector& amplitudes() const { return chi_; }
  void set_amplitudes(Vector chi);
  // gamma_i at the lagged amplitudes, with d gamma_i / d chi_i and d gamma_i / d(controls).
  double scale(int i, const Vector& p, double* slope = nullptr, Vector* control_gradient = nullptr) const;
  // The damping scale curve of example i at amplitude chi.
  double curve(int i, const Vector& p, double chi) const;

 private:
  struct Scales;  // gamma, kappa and their derivatives at the lagged amplitudes
  Scales scales(const Vector& p) const;
  Vector transform(const Scales& s, const Vector& v) const;  // T v
  // d(w^T dD/dv)/dgamma_i for every example.
  Vector scale_mixed(const Scales& s, const Vector& v, const Vector& p, const Vector& w) const;
  Vector x_start_, v_start_;  // the lagged state (empty until set_step_start)
  std::unique_ptr<RayleighDamping> base_;
  Matrix examples_, mass_examples_;
  Vector frequencies_, rest_, amplitude_scale_, chi_;
  std::vector<MonotoneCubic> curves_;
  std::vector<int> curve_begin_;
  int curve_offset_, num_controls_ = 0;
  double smoothing_;
};

}  // namespace tailor
