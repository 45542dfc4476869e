#pragma once
// The parameters of one discrete elastic rod, as named blocks of the Model's parameter vector:
//   <prefix>_youngs_modulus  per edge [pressure]
//   <prefix>_shear_modulus   per edge [pressure]
//   <prefix>_radius          per edge, the cross-section size r (cross_section.hpp) [length]
//   <prefix>_rest_length     per edge [length]
//   <prefix>_rest_curvature  2 per interior vertex i: (kappa1, kappa2) at p[offset + 2 i + a]
//                            (dimensionless, the scale of 2 tan(turning angle / 2))
//   <prefix>_rest_twist      per interior vertex [rad]
#include <string>

#include "forward/core/model.hpp"
#include "forward/rods/cross_section.hpp"
#include "forward/rods/discrete_rod.hpp"

namespace tailor {

struct RodParameterBlocks {
  int youngs_modulus = -1, shear_modulus = -1, radius = -1, rest_length = -1, rest_curvature = -1,
      rest_twist = -1;
};

// Uniform material of a rod. Throws std::invalid_argument (from validate()) on non-positive
// moduli or radius.
struct RodMaterial {
  double youngs_modulus = 1.0;
  double shear_modulus = 0.5;
  double radius = 1.0;
  CrossSection section;
  void validate() const;
};

// Appends the six blocks (names above) for `rod`; throws if a name is taken.
RodParameterBlocks add_rod_parameters(ParameterLayout& layout, const DiscreteRod& rod,
                                      const std::string& prefix = "rod");

// Fills the rod's blocks of p: uniform material, rest lengths of the rest positions, and rest
// curvatures and twists equal to the strains of the rest state (so the rest shape is
// stress-free). The rod's stored frames must be those of the rest state.
void write_rod_parameters(const DiscreteRod& rod, const RodParameterBlocks& blocks,
                          const RodMaterial& material, Vector& p);

// The strains (kappa1, kappa2, twist) of interior vertex i at state x (rod_kinematics.hpp).
Eigen::Vector3d bend_twist_strain_values(const DiscreteRod& rod, const Vector& x, int interior);

}  // namespace tailor
