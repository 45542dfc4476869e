// Quadrature rules on the reference simplices integrate every monomial up to their stated
// degree exactly (int x^a y^b z^c = a! b! c! / (a + b + c + D)!), and the P2 shape functions
// are a Kronecker basis at their nodes, sum to one, and have the gradients of their values.
#include "forward/fem/simplex_quadrature.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "forward/fem/p2_shape_functions.hpp"

namespace tailor::simplex_quadrature_test {
namespace {

double factorial(int n) { return std::tgamma(n + 1.0); }

template <int D, int N>
void expect_exact_to_degree(const SimplexRule<D, N>& rule, int degree) {
  for (int a = 0; a <= degree; ++a)
    for (int b = 0; b <= (D >= 2 ? degree - a : 0); ++b)
      for (int c = 0; c <= (D == 3 ? degree - a - b : 0); ++c) {
        double sum = 0.0;
        for (int q = 0; q < N; ++q) {
          const auto& xi = rule.points[static_cast<std::size_t>(q)];
          double m = std::pow(xi[0], a);
          if constexpr (D >= 2) m *= std::pow(xi[1], b);
          if constexpr (D == 3) m *= std::pow(xi[2], c);
          sum += rule.weights[static_cast<std::size_t>(q)] * m;
        }
        const double exact = factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + D);
        EXPECT_NEAR(sum, exact, 1e-14) << "D = " << D << ", x^" << a << " y^" << b << " z^" << c;
      }
}

TEST(SimplexQuadrature, RulesAreExactToTheirDegree) {
  expect_exact_to_degree(segment_rule_degree5(), 5);
  expect_exact_to_degree(triangle_rule_degree2(), 2);
  expect_exact_to_degree(triangle_rule_degree4(), 4);
  expect_exact_to_degree(tetrahedron_rule_degree2(), 2);
  expect_exact_to_degree(tetrahedron_rule_degree4(), 4);
}

// The P2 nodes in local coordinates: corners, then edge midpoints in simplex_edges order.
template <int D>
std::vector<Eigen::Matrix<double, D, 1>> p2_nodes() {
  std::vector<Eigen::Matrix<double, D, 1>> corners(D + 1, Eigen::Matrix<double, D, 1>::Zero());
  for (int i = 0; i < D; ++i) corners[static_cast<std::size_t>(i + 1)][i] = 1.0;
  std::vector<Eigen::Matrix<double, D, 1>> nodes = corners;
  for (const auto& e : simplex_edges<D>())
    nodes.push_back(0.5 * (corners[static_cast<std::size_t>(e[0])] + corners[static_cast<std::size_t>(e[1])]));
  return nodes;
}

template <int D>
void check_shape_functions() {
  using S = P2Shape<D>;
  const auto nodes = p2_nodes<D>();
  ASSERT_EQ(static_cast<int>(nodes.size()), S::kNodes);
  for (int b = 0; b < S::kNodes; ++b) {
    const auto N = S::values(nodes[static_cast<std::size_t>(b)]);
    for (int a = 0; a < S::kNodes; ++a) EXPECT_NEAR(N[a], a == b ? 1.0 : 0.0, 1e-15);
  }
  Eigen::Matrix<double, D, 1> xi = Eigen::Matrix<double, D, 1>::Constant(0.13);
  xi[0] = 0.21;
  EXPECT_NEAR(S::values(xi).sum(), 1.0, 1e-15);
  EXPECT_LT(S::gradients(xi).colwise().sum().norm(), 1e-14);
  const double h = 1e-6;
  for (int j = 0; j < D; ++j) {
    Eigen::Matrix<double, D, 1> step = Eigen::Matrix<double, D, 1>::Zero();
    step[j] = h;
    const typename S::Values difference = (S::values(xi + step) - S::values(xi - step)) / (2 * h);
    EXPECT_LT((difference - S::gradients(xi).col(j)).norm(), 1e-9);
  }
}

TEST(P2Shape, KroneckerPartitionOfUnityAndGradients) {
  check_shape_functions<1>();
  check_shape_functions<2>();
  check_shape_functions<3>();
}

}  // namespace
}  // namespace tailor::simplex_quadrature_test
