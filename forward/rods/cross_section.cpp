#include "forward/rods/cross_section.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace tailor {

void CrossSection::validate() const {
  if (!(aspect > 0.0) || !std::isfinite(aspect))
    throw std::invalid_argument("CrossSection: aspect ratio must be positive, got " + std::to_string(aspect));
  if (shape == CrossSectionShape::circle && aspect != 1.0)
    throw std::invalid_argument("CrossSection: a circle has aspect ratio 1 (use an ellipse)");
}

// Semi-axes a = r (along m1), b = aspect r. Ellipse: A = pi a b, I1 = pi a^3 b / 4 (second
// moment about the m2 axis), I2 = pi a b^3 / 4, J = pi a^3 b^3 / (a^2 + b^2) (Saint-Venant).
// Rectangle with half-sides a >= or <= b: A = 4 a b, I1 = 4 a^3 b / 3, I2 = 4 a b^3 / 3, and the
// torsion constant of Roark's formulas, J = c d^3 (16/3 - 3.36 (d/c)(1 - d^4 / (12 c^4))) with
// c the larger and d the smaller half-side (error below 4% over all aspect ratios).
double CrossSection::area_coefficient() const {
  if (shape == CrossSectionShape::rectangle) return 4.0 * aspect;
  return std::numbers::pi * aspect;
}
double CrossSection::bending_coefficient1() const {
  if (shape == CrossSectionShape::rectangle) return 4.0 * aspect / 3.0;
  return std::numbers::pi * aspect / 4.0;
}
double CrossSection::bending_coefficient2() const {
  const double b3 = aspect * aspect * aspect;
  if (shape == CrossSectionShape::rectangle) return 4.0 * b3 / 3.0;
  return std::numbers::pi * b3 / 4.0;
}
double CrossSection::torsion_coefficient() const {
  const double b = aspect;
  if (shape == CrossSectionShape::rectangle) {
    const double c = std::max(1.0, b), d = std::min(1.0, b);
    return c * d * d * d * (16.0 / 3.0 - 3.36 * (d / c) * (1.0 - std::pow(d / c, 4) / 12.0));
  }
  return std::numbers::pi * b * b * b / (1.0 + b * b);
}

CrossSectionShape cross_section_shape_from_string(const std::string& name) {
  if (name == "circle") return CrossSectionShape::circle;
  if (name == "ellipse") return CrossSectionShape::ellipse;
  if (name == "rectangle") return CrossSectionShape::rectangle;
  throw std::invalid_argument("unknown cross-section shape '" + name +
                              "' (expected circle, ellipse or rectangle)");
}

std::string to_string(CrossSectionShape shape) {
  switch (shape) {
    case CrossSectionShape::circle:
      return "circle";
    case CrossSectionShape::ellipse:
      return "ellipse";
    case CrossSectionShape::rectangle:
      return "rectangle";
  }
  return "unknown";
}

}  // namespace tailor
