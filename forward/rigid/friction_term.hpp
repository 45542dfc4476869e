#pragma once
// FrictionTerm: IPC's smoothed, lagged friction (forward/contact/friction.hpp) between the
// bodies of a RigidContactTerm (rigid bodies and deformable surfaces, contact_bodies.hpp), as an
// EnergyTerm of a time step's incremental potential:
//   D(q) = sum_k mu lambda_k f0(|Gamma_k (x_k(q) - x_k^t)|),
// with the pairs, their normal forces lambda_k and tangent maps Gamma_k lagged by lag() (at the
// start of the step, or at a previous solution for lagged iterations) and x^t the stencils at
// the start of the step. Derivatives through x(q) by ContactBodies::add_stencil (exact; the
// rotation's second derivative makes the rigid Hessian indefinite, projected in projected mode).
// Friction is dissipative: D is a potential only while the lagged data are held fixed.
#include <vector>

#include "forward/contact/friction.hpp"
#include "forward/rigid/rigid_contact_term.hpp"

namespace tailor::rigid {

class FrictionTerm final : public EnergyTerm {
 public:
  // `contact` must outlive the term. Throws std::invalid_argument on mu < 0 or eps_v <= 0.
  FrictionTerm(const RigidContactTerm& contact, contact::FrictionOptions options);

  std::string name() const override { return "friction"; }
  void evaluate(const Vector& q, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;

  // Lags the pairs active at q_lag (normal forces with the contact term's current stiffness),
  // displacements measured from q_start, threshold eps = eps_v h for the step h.
  void lag(const Vector& q_lag, const Vector& q_start, double time_step);
  // Drops every pair (no friction until the next lag()).
  void clear() { pairs_.clear(); }
  const std::vector<contact::FrictionPair>& pairs() const { return pairs_; }
  const contact::FrictionOptions& options() const { return options_; }
  double threshold() const { return threshold_; }  // eps = eps_v h [length]
  // Pairs whose slip |u| at q is at least the threshold (sliding) and below it (sticking).
  std::pair<int, int> sliding_and_sticking(const Vector& q) const;

 private:
  Eigen::Matrix<double, 12, 1> stencil(const contact::Positions& x, const std::array<int, 4>& v) const;
  const RigidContactTerm& contact_;
  contact::FrictionOptions options_;
  contact::SlotMap slots_;
  std::vector<contact::FrictionPair> pairs_;
  double threshold_ = 0.0;
};

}  // namespace tailor::rigid
