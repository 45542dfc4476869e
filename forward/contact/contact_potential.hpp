#pragma once
// ContactPotential: the IPC barrier energy of a ContactSurface (Li et al. 2020, eq. 8),
//   B(x) = kappa * ( sum_{point-triangle pairs} b(d^2) + sum_{edge-edge pairs} m(c) b(d^2) ),
// over surface positions x, independent of how they map to DOFs (ContactTerm for vertex
// DOFs, RigidContactTerm for rigid bodies). Pairs come from the broad phase within d_hat;
// each active pair contributes on its stencil of four surface vertices (pair_potential.hpp).
#include <array>
#include <functional>
#include <limits>

#include "forward/contact/additive_ccd.hpp"
#include "forward/contact/broad_phase.hpp"

namespace tailor::contact {

struct ContactOptions {
  double activation_distance = 1e-3;  // d_hat [length]: pairs closer than this repel
  double stiffness = 1.0;             // kappa [energy / length^4] (b acts on squared distances)
  CcdOptions ccd;                     // for max_step
};

// One active pair with its stencil (surface vertices) and kappa-scaled derivatives.
struct ActivePair {
  PairKind kind;
  std::array<int, 4> vertices;
  PairDerivatives derivatives;
};

class ContactPotential {
 public:
  // `rest`: rest positions (one row per surface vertex) for the mollifier thresholds.
  // Throws std::invalid_argument on a non-positive d_hat or kappa or mismatched sizes.
  ContactPotential(ContactSurface surface, const Positions& rest, ContactOptions options);

  const ContactSurface& surface() const { return surface_; }
  const ContactOptions& options() const { return options_; }
  void set_stiffness(double kappa);

  // The stencil of a candidate pair and its points at x.
  std::array<int, 4> stencil(PairKind kind, const std::array<int, 2>& pair) const;
  double mollifier_eps(const std::array<int, 2>& edge_pair) const;

  // B(x) (+infinity if a pair intersects).
  double energy(const Positions& x) const;
  // Calls `visit` for every active pair with its derivatives (scaled by kappa) when
  // `derivatives`, or its value only.
  void for_each_active(const Positions& x, bool derivatives,
                       const std::function<void(const ActivePair&)>& visit) const;
  // Largest safe fraction of the straight step x -> x + dx (ACCD on the broad phase's
  // candidates over the swept boxes); 1 when nothing can touch.
  double max_step(const Positions& x, const Positions& dx) const;

  // Diagnostics: the smallest distance over pairs within `range` (infinity if none), and the
  // number of active pairs.
  double min_distance(const Positions& x, double range) const;
  int num_active(const Positions& x) const;

 private:
  ContactSurface surface_;
  ContactOptions options_;
  std::vector<double> edge_rest_length_squared_;
};

}  // namespace tailor::contact
