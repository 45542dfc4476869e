#pragma once
// ContactTerm: the IPC barrier (contact_potential.hpp) as an EnergyTerm over vertex DOFs,
// e.g. the boundary triangles of FEM meshes, rod edges or fixed obstacles: surface vertex v
// sits at x[vertex_dofs[v] + k], k = 0, 1, 2 (world positions [length]).
//
// Hessian pattern. The pairs in contact change during a solve while the Model's pattern is
// fixed when the solver is built (forward/core/assembler.hpp). The term therefore announces
// the dense coupling of the vertex sets that may meet:
//   pattern_distance = infinity (default): every surface DOF with every other (exact for any
//     motion; (3 n_s)^2 slots, for surfaces of up to a few hundred vertices);
//   pattern_distance = r: the stencils of the broad-phase candidates within r at the state
//     given to update_pattern() (the rest state at construction). Call update_pattern()
//     between solves (and build a new solver); a pair outside it during a solve throws
//     std::runtime_error naming the DOFs, so a too-small r never gives a silently wrong
//     Hessian.
// max_step() is conservative additive CCD (additive_ccd.hpp) on straight DOF motion.
#include <limits>
#include <vector>

#include "forward/contact/contact_potential.hpp"
#include "forward/contact/slot_map.hpp"
#include "forward/core/energy_term.hpp"

namespace tailor {

class ContactTerm final : public EnergyTerm {
 public:
  // Throws std::invalid_argument when vertex_dofs does not match the surface or points past
  // the end of `rest_state` (whose size is the number of DOFs).
  ContactTerm(contact::ContactSurface surface, std::vector<int> vertex_dofs, const Vector& rest_state,
              contact::ContactOptions options,
              double pattern_distance = std::numeric_limits<double>::infinity());

  std::string name() const override { return "contact"; }
  void evaluate(const Vector& x, const Vector& p, const EnergyRequest& request) const override;
  void hessian_pattern(HessianPattern& pattern) const override;
  double max_step(const Vector& x, const Vector& dx) const override;

  // Re-chooses the pattern from the candidates at x (no effect with an infinite distance).
  void update_pattern(const Vector& x);
  contact::Positions positions(const Vector& x) const;
  const contact::ContactPotential& potential() const { return potential_; }
  contact::ContactPotential& potential() { return potential_; }

 private:
  std::vector<int> stencil_dofs(const std::array<int, 4>& vertices) const;
  contact::ContactPotential potential_;
  std::vector<int> vertex_dofs_;
  int num_dofs_;
  double pattern_distance_;
  contact::SlotMap slots_;
};

}  // namespace tailor
