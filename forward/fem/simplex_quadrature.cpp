#include "forward/fem/simplex_quadrature.hpp"

#include <cmath>

namespace tailor {

const SimplexRule<1, 3>& segment_rule_degree5() {
  static const SimplexRule<1, 3> rule = [] {
    SimplexRule<1, 3> r;
    const double d = 0.5 * std::sqrt(0.6);  // Gauss points +-sqrt(3/5) on [-1, 1], mapped to [0, 1]
    r.points[0] << 0.5 - d;
    r.points[1] << 0.5;
    r.points[2] << 0.5 + d;
    r.weights = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
    return r;
  }();
  return rule;
}

const SimplexRule<2, 3>& triangle_rule_degree2() {
  static const SimplexRule<2, 3> rule = [] {
    SimplexRule<2, 3> r;
    // Barycentric (2/3, 1/6, 1/6) and its permutations; xi = the last two coordinates.
    r.points[0] << 1.0 / 6.0, 1.0 / 6.0;
    r.points[1] << 2.0 / 3.0, 1.0 / 6.0;
    r.points[2] << 1.0 / 6.0, 2.0 / 3.0;
    r.weights = {1.0 / 6.0, 1.0 / 6.0, 1.0 / 6.0};
    return r;
  }();
  return rule;
}

const SimplexRule<2, 6>& triangle_rule_degree4() {
  static const SimplexRule<2, 6> rule = [] {
    SimplexRule<2, 6> r;
    // Two orbits of barycentric (a, b, b): weights relative to the area, times 1/2.
    const double a1 = 0.108103018168070, b1 = 0.445948490915965, w1 = 0.223381589678011;
    const double a2 = 0.816847572980459, b2 = 0.091576213509771, w2 = 0.109951743655322;
    r.points[0] << b1, b1;
    r.points[1] << a1, b1;
    r.points[2] << b1, a1;
    r.points[3] << b2, b2;
    r.points[4] << a2, b2;
    r.points[5] << b2, a2;
    r.weights = {0.5 * w1, 0.5 * w1, 0.5 * w1, 0.5 * w2, 0.5 * w2, 0.5 * w2};
    return r;
  }();
  return rule;
}

const SimplexRule<3, 4>& tetrahedron_rule_degree2() {
  static const SimplexRule<3, 4> rule = [] {
    SimplexRule<3, 4> r;
    const double a = (5.0 + 3.0 * std::sqrt(5.0)) / 20.0, b = (5.0 - std::sqrt(5.0)) / 20.0;
    r.points[0] << b, b, b;
    r.points[1] << a, b, b;
    r.points[2] << b, a, b;
    r.points[3] << b, b, a;
    r.weights = {1.0 / 24.0, 1.0 / 24.0, 1.0 / 24.0, 1.0 / 24.0};
    return r;
  }();
  return rule;
}

}  // namespace tailor
