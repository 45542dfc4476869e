#pragma once
// Cross-sections of a discrete elastic rod, scaled by one size parameter r per edge (the
// radius of a circle, the semi-axis along m1 of an ellipse, half the side along m1 of a
// rectangle) with a fixed aspect ratio (extent along m2 / extent along m1):
//   area A = a_coef r^2, bending moments of area I1 = i1_coef r^4 (bending towards m1,
//   curvature kappa_1), I2 = i2_coef r^4 (towards m2), torsion constant J = j_coef r^4.
// Units: r [length]; A [length^2]; I, J [length^4].
#include <string>

namespace tailor {

enum class CrossSectionShape { circle, ellipse, rectangle };

struct CrossSection {
  CrossSectionShape shape = CrossSectionShape::circle;
  double aspect = 1.0;  // extent along m2 / extent along m1 (1 for a circle)

  // Throws std::invalid_argument for aspect <= 0 or a circle with aspect != 1.
  void validate() const;
  double area_coefficient() const;      // A / r^2
  double bending_coefficient1() const;  // I1 / r^4
  double bending_coefficient2() const;  // I2 / r^4
  double torsion_coefficient() const;   // J / r^4
};

// "circle", "ellipse", "rectangle"; throws std::invalid_argument naming the accepted values.
CrossSectionShape cross_section_shape_from_string(const std::string& name);
std::string to_string(CrossSectionShape shape);

}  // namespace tailor
