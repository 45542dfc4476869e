#pragma once
// TorusFrictionTerm: IPC's smoothed, lagged friction (Li et al. 2020, section 5;
// forward/contact/friction.hpp) between implicit tori (docs/tori.md), an EnergyTerm over the rigid
// DOFs (torus i owns q[6i .. 6i+5] = (T_i, w_i)), next to the TorusContactTerm whose barrier
// supplies the normal forces.
//
// Lagged by lag() at q_lag (the start of the time step), for every pair with 0 < d < d_hat:
//   - the closest points x_a, x_b of the two surfaces (the distance query's minimizers: circular
//     tubes c_a + r_a n and c_b - r_b n from the core points, elliptic ones the surface points),
//     held as material points X = Q(w)^T (x - T) of their bodies;
//   - the normal n = (x_b - x_a) / |x_b - x_a| (a circular pair: the core points' direction) and
//     the tangent basis P (3 x 2) of contact::tangent_basis;
//   - the normal force lambda = -d(kappa b(d^2))/dd = kappa |b'(d^2)| 2 d (b the barrier on squared
//     distances, kappa the contact term's stiffness at the time of lag()).
// With these fixed, the material points follow the rigid motion, x_a(q) = T_a + Q(w_a) X_a, and
//   D(q) = sum_pairs mu lambda f0(|u|),   u = P^T ((x_a(q) - x_a^t) - (x_b(q) - x_b^t)),
// x^t the points at q_start and f0 the smoothing of contact::friction_f0 with eps = eps_v h. The
// pair potential in the two points is contact::friction_pair_potential (on a stencil whose
// tangent map is Gamma = [P^T, -P^T, 0, 0]); its gradient g_x and Hessian H_x go to the DOFs by
//   J = dx/d(T, w) = [I, Q_1 X, Q_2 X, Q_3 X]   (Q_k = dQ/dw_k, forward/rigid/rotation.hpp),
//   g = J^T g_x,   H = J^T H_x J + sum_i (g_x)_i d2x_i/dw dw,   d2x/dw_k dw_l = Q_kl X,
// exact; the last (rotational curvature) term makes H indefinite, projected per pair (12 x 12)
// in projected mode. Friction is dissipative: D is a potential only while the lagged data stay.
//
// Poses come from q with the shapes given to the contact term (no radii or placements from p:
// such a contact term is refused). Hessian pattern: a 12 x 12 block per candidate pair of the
// contact term.
#include <vector>

#include "forward/contact/friction.hpp"
#include "forward/tori/torus_contact_term.hpp"

namespace tailor::tori {

struct TorusFrictionOptions {
  contact::FrictionOptions friction;  // mu and eps_v
  // false drops the rotational curvature term sum_i (g_x)_i d2x_i/dw2 of the Hessian (a
  // deliberately wrong Hessian: only for the test that shows the derivative check catches it).
  bool rotation_curvature = true;
};

// One lagged pair.
struct TorusFrictionPair {
  int a = 0, b = 0;
  double distance = 0.0;                                   // d at q_lag
  Eigen::Vector3d material_a, material_b;                  // X_a, X_b (body frames)
  Eigen::Vector3d normal;                                  // n, from a to b
  contact::FrictionPair stencil;                           // Gamma, lambda, (x_a^t, x_b^t, 0, 0)
  int slot = 0;                                            // first Hessian slot of the pair
};

class TorusFrictionTerm final : public EnergyTerm {
 public:
  // `contact` must outlive the term; `system` is only checked against it (one torus per body).
  // Throws std::invalid_argument on mu < 0, eps_v <= 0, a contact term reading radii or
  // placements from p, or a body count that differs from the contact term's tori.
  TorusFrictionTerm(const rigid::RigidBodySystem& system, const TorusContactTerm& contact,
                    TorusFrictionOptions options);

  std::string name() const override { return "torus_friction"; }
  void evaluate(const Vector& q, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;

  // Lags the pairs within d_hat at q_lag, displacements measured from q_start, eps = eps_v h.
  // Throws std::invalid_argument on a non-positive time step, std::runtime_error when a pair
  // that is not a candidate of the contact term is within d_hat.
  void lag(const Vector& q_lag, const Vector& q_start, double time_step);
  void clear() { pairs_.clear(); }
  const std::vector<TorusFrictionPair>& pairs() const { return pairs_; }
  const TorusFrictionOptions& options() const { return options_; }
  double threshold() const { return threshold_; }  // eps = eps_v h [length]
  // The relative tangential displacement |u| of each lagged pair's closest points at q.
  std::vector<double> slips(const Vector& q) const;
  // Pairs whose slip at q is at least the threshold (sliding) and below it (sticking).
  std::pair<int, int> sliding_and_sticking(const Vector& q) const;

 private:
  const TorusContactTerm& contact_;
  TorusFrictionOptions options_;
  std::vector<TorusFrictionPair> pairs_;
  double threshold_ = 0.0;
};

}  // namespace tailor::tori
