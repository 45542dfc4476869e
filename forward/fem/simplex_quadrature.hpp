#pragma once
// Quadrature rules on the reference simplices (points in local coordinates xi, the reference
// simplex being {xi_i >= 0, sum xi_i <= 1}; weights sum to its measure: 1 for the segment,
// 1/2 for the triangle, 1/6 for the tetrahedron). Symmetric rules with positive weights and
// their points inside:
//   segment_rule_degree5      3-point Gauss-Legendre, exact to degree 5 (Abramowitz & Stegun 25.4.29)
//   triangle_rule_degree2     3 points at barycentric (2/3, 1/6, 1/6) and permutations, degree 2
//                             (Strang & Fix 1973, Table 4.1; Zienkiewicz & Taylor, Vol. 1, Table 5.3)
//   triangle_rule_degree4     6 points, degree 4 (Dunavant 1985, IJNME 21:1129, rule 4)
//   tetrahedron_rule_degree2  4 points at barycentric (a, b, b, b) and permutations,
//                             a = (5 + 3 sqrt 5) / 20, b = (5 - sqrt 5) / 20, degree 2
//                             (Keast 1986, CMAME 55:339; Zienkiewicz & Taylor, Vol. 1, Table 5.4)
//   tetrahedron_rule_degree4  11 points, degree 4 (Keast 1986, rule with the centroid weight
//                             -74/5625: one negative weight, the price of 11 points; fine for the
//                             mass matrix, whose integrand N_a N_b it integrates exactly)
// The tests (tests/forward/fem/simplex_quadrature_test.cpp) integrate every monomial up to the
// stated degree against the closed form  int x^a y^b z^c = a! b! c! / (a + b + c + D)!.
#include <Eigen/Core>
#include <array>

namespace tailor {

template <int D, int N>
struct SimplexRule {
  static constexpr int kDim = D;
  static constexpr int kPoints = N;
  std::array<Eigen::Matrix<double, D, 1>, N> points;
  std::array<double, N> weights;
};

const SimplexRule<1, 3>& segment_rule_degree5();
const SimplexRule<2, 3>& triangle_rule_degree2();
const SimplexRule<2, 6>& triangle_rule_degree4();
const SimplexRule<3, 4>& tetrahedron_rule_degree2();
const SimplexRule<3, 11>& tetrahedron_rule_degree4();

}  // namespace tailor
