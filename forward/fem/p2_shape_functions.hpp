#pragma once
// Quadratic (P2) Lagrange shape functions on the reference simplex of dimension D (1: segment,
// 2: triangle, 3: tetrahedron) in local coordinates xi (the reference simplex is
// {xi_i >= 0, sum xi_i <= 1}). With the barycentric coordinates L_0 = 1 - sum xi, L_i = xi_i:
//   corner a:         N_a  = L_a (2 L_a - 1)
//   edge (a, b):      N_ab = 4 L_a L_b
// (Zienkiewicz & Taylor, The Finite Element Method, Vol. 1, 6th ed., section 8.8). Nodes in the
// order of forward/mesh/quadratic_mesh.hpp: the D + 1 corners, then the edges of simplex_edges<D>.
#include <Eigen/Core>

#include "forward/mesh/quadratic_mesh.hpp"

namespace tailor {

template <int D>
struct P2Shape {
  static constexpr int kNodes = (D + 1) * (D + 2) / 2;
  using Point = Eigen::Matrix<double, D, 1>;
  using Values = Eigen::Matrix<double, kNodes, 1>;
  using Gradients = Eigen::Matrix<double, kNodes, D>;  // row a: dN_a / dxi

  static Values values(const Point& xi) {
    const Eigen::Matrix<double, D + 1, 1> L = barycentric(xi);
    Values N;
    for (int a = 0; a <= D; ++a) N[a] = L[a] * (2.0 * L[a] - 1.0);
    int i = D + 1;
    for (const auto& e : simplex_edges<D>()) N[i++] = 4.0 * L[e[0]] * L[e[1]];
    return N;
  }

  static Gradients gradients(const Point& xi) {
    const Eigen::Matrix<double, D + 1, 1> L = barycentric(xi);
    // dL_0/dxi = -1 (every component), dL_a/dxi = e_{a-1}.
    Eigen::Matrix<double, D + 1, D> dL = Eigen::Matrix<double, D + 1, D>::Zero();
    dL.row(0).setConstant(-1.0);
    dL.template bottomRows<D>().setIdentity();
    Gradients G;
    for (int a = 0; a <= D; ++a) G.row(a) = (4.0 * L[a] - 1.0) * dL.row(a);
    int i = D + 1;
    for (const auto& e : simplex_edges<D>()) G.row(i++) = 4.0 * (L[e[1]] * dL.row(e[0]) + L[e[0]] * dL.row(e[1]));
    return G;
  }

 private:
  static Eigen::Matrix<double, D + 1, 1> barycentric(const Point& xi) {
    Eigen::Matrix<double, D + 1, 1> L;
    L[0] = 1.0 - xi.sum();
    L.template tail<D>() = xi;
    return L;
  }
};

}  // namespace tailor
