#include "forward/rods/rod_parameters.hpp"

#include <cmath>
#include <stdexcept>

#include "forward/rods/rod_kinematics.hpp"
#include "forward/rods/rod_stencils.hpp"

namespace tailor {

void RodMaterial::validate() const {
  auto positive = [](double v, const char* what) {
    if (!(v > 0.0) || !std::isfinite(v))
      throw std::invalid_argument(std::string("rod material: ") + what + " must be positive, got " +
                                  std::to_string(v));
  };
  positive(youngs_modulus, "youngs_modulus");
  positive(shear_modulus, "shear_modulus");
  positive(radius, "radius");
  section.validate();
}

RodParameterBlocks add_rod_parameters(ParameterLayout& layout, const DiscreteRod& rod,
                                      const std::string& prefix) {
  RodParameterBlocks b;
  b.youngs_modulus = layout.add(prefix + "_youngs_modulus", rod.num_edges());
  b.shear_modulus = layout.add(prefix + "_shear_modulus", rod.num_edges());
  b.radius = layout.add(prefix + "_radius", rod.num_edges());
  b.rest_length = layout.add(prefix + "_rest_length", rod.num_edges());
  b.rest_curvature = layout.add(prefix + "_rest_curvature", 2 * rod.num_interior());
  b.rest_twist = layout.add(prefix + "_rest_twist", rod.num_interior());
  return b;
}

void write_rod_parameters(const DiscreteRod& rod, const RodParameterBlocks& blocks,
                          const RodMaterial& material, Vector& p) {
  material.validate();
  const int ne = rod.num_edges();
  p.segment(blocks.youngs_modulus, ne).setConstant(material.youngs_modulus);
  p.segment(blocks.shear_modulus, ne).setConstant(material.shear_modulus);
  p.segment(blocks.radius, ne).setConstant(material.radius);
  p.segment(blocks.rest_length, ne) = rod.rest_lengths();
  Vector x = Vector::Zero(rod.dof_end());
  rod.write_rest_state(x);
  for (int i = 0; i < rod.num_interior(); ++i) {
    const Eigen::Vector3d s = bend_twist_strain_values(rod, x, i);
    p[blocks.rest_curvature + 2 * i] = s[0];
    p[blocks.rest_curvature + 2 * i + 1] = s[1];
    p[blocks.rest_twist + i] = s[2];
  }
}

Eigen::Vector3d bend_twist_strain_values(const DiscreteRod& rod, const Vector& x, int interior) {
  const auto dofs = rod_detail::bend_twist_dofs(rod, interior);
  rod_detail::BendTwistLocal local;
  for (int r = 0; r < rod_detail::kBendTwistDofs; ++r) local[r] = x[dofs[static_cast<std::size_t>(r)]];
  const auto s = rod_detail::bend_twist_strains<rod_detail::Dual0>(local, rod_detail::stored_frames(rod, interior));
  return {s.kappa1.v, s.kappa2.v, s.twist.v};
}

}  // namespace tailor
