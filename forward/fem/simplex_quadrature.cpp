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

const SimplexRule<3, 11>& tetrahedron_rule_degree4() {
  static const SimplexRule<3, 11> rule = [] {
    SimplexRule<3, 11> r;
    // Orbits in barycentric coordinates: the centroid; (a, a, a, 1 - 3a) with a = 1/14; and
    // (b, b, c, c) with b = (1 + sqrt(5/14)) / 4, c = (1 - sqrt(5/14)) / 4. xi = the last three.
    const double a = 1.0 / 14.0, d = 1.0 - 3.0 * a;
    const double b = 0.25 * (1.0 + std::sqrt(5.0 / 14.0)), c = 0.25 * (1.0 - std::sqrt(5.0 / 14.0));
    r.points[0] << 0.25, 0.25, 0.25;
    r.points[1] << a, a, a;
    r.points[2] << d, a, a;
    r.points[3] << a, d, a;
    r.points[4] << a, a, d;
    // (L0, L1, L2, L3) with two b's and two c's: xi = (L1, L2, L3).
    r.points[5] << b, c, c;   // (b, b, c, c)
    r.points[6] << c, b, c;   // (b, c, b, c)
    r.points[7] << c, c, b;   // (b, c, c, b)
    r.points[8] << c, b, b;   // (c, c, b, b)
    r.points[9] << b, c, b;   // (c, b, c, b)
    r.points[10] << b, b, c;  // (c, b, b, c)
    const double w0 = -74.0 / 5625.0, w1 = 343.0 / 45000.0, w2 = 56.0 / 2250.0;
    r.weights = {w0, w1, w1, w1, w1, w2, w2, w2, w2, w2, w2};
    return r;
  }();
  return rule;
}

}  // namespace tailor
