#pragma once
// Small fixed-size tensor helpers shared by the material models (private to forward/fem/materials).
//
// Conventions follow material.hpp: vec(F) is column-major, entry (i, j) of a Dim x Dim matrix
// is component i + Dim * j, and a tangent is d vec(P) / d vec(F).
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

namespace tailor::material_detail {

template <int Dim>
using Mat = Eigen::Matrix<double, Dim, Dim>;
template <int Dim>
using VecN = Eigen::Matrix<double, Dim * Dim, 1>;
template <int Dim>
using Tangent = Eigen::Matrix<double, Dim * Dim, Dim * Dim>;

// vec(A) as a view (Eigen stores fixed matrices column-major, which is exactly vec).
template <int Dim>
inline Eigen::Map<const VecN<Dim>> vec(const Mat<Dim>& A) {
  return Eigen::Map<const VecN<Dim>>(A.data());
}
template <int Dim>
inline Eigen::Map<VecN<Dim>> vec(Mat<Dim>& A) {
  return Eigen::Map<VecN<Dim>>(A.data());
}

// T += s * (I + K), K the commutation matrix (K vec(A) = vec(A^T)): the tangent of the
// stress 2 s sym(F), i.e. of the energy s tr(sym(F)^2).
template <int Dim>
inline void add_identity_plus_commutation(double s, Tangent<Dim>& T) {
  for (int j = 0; j < Dim; ++j)
    for (int i = 0; i < Dim; ++i) {
      T(i + Dim * j, i + Dim * j) += s;
      T(i + Dim * j, j + Dim * i) += s;
    }
}

// T += s * vec(I) vec(I)^T.
template <int Dim>
inline void add_identity_outer(double s, Tangent<Dim>& T) {
  for (int j = 0; j < Dim; ++j)
    for (int i = 0; i < Dim; ++i) T(i + Dim * i, j + Dim * j) += s;
}

// Cofactor matrix cof(F) = dJ/dF = J F^{-T} (defined for every F, also singular ones).
inline Mat<2> cofactor(const Mat<2>& F) {
  Mat<2> C;
  C << F(1, 1), -F(1, 0), -F(0, 1), F(0, 0);
  return C;
}
inline Mat<3> cofactor(const Mat<3>& F) {
  Mat<3> C;
  C.col(0) = F.col(1).cross(F.col(2));
  C.col(1) = F.col(2).cross(F.col(0));
  C.col(2) = F.col(0).cross(F.col(1));
  return C;
}

// T += s * d vec(cof F) / d vec(F), the Hessian of J = det F (linear in F in 3D, constant in 2D).
inline void add_determinant_hessian(double s, const Mat<2>& /*F*/, Tangent<2>& T) {
  // vec(F) = (a, c, b, d) for F = [a b; c d]; vec(cof F) = (d, -b, -c, a).
  T(0, 3) += s;
  T(3, 0) += s;
  T(1, 2) -= s;
  T(2, 1) -= s;
}
inline void add_determinant_hessian(double s, const Mat<3>& F, Tangent<3>& T) {
  // With columns f0, f1, f2: cof = [f1 x f2, f2 x f0, f0 x f1], and d(a x b) = da x b + a x db,
  // so block (column a of cof, column b of F) is +-[f_c]_x with (a, b, c) a permutation.
  auto add_cross = [&](int row_block, int col_block, const Eigen::Vector3d& v, double sign) {
    const double w = sign * s;
    // [v]_x = [0 -v2 v1; v2 0 -v0; -v1 v0 0]
    T(3 * row_block + 0, 3 * col_block + 1) -= w * v(2);
    T(3 * row_block + 0, 3 * col_block + 2) += w * v(1);
    T(3 * row_block + 1, 3 * col_block + 0) += w * v(2);
    T(3 * row_block + 1, 3 * col_block + 2) -= w * v(0);
    T(3 * row_block + 2, 3 * col_block + 0) -= w * v(1);
    T(3 * row_block + 2, 3 * col_block + 1) += w * v(0);
  };
  // d(f1 x f2) = -[f2]_x df1 + [f1]_x df2, and cyclically.
  add_cross(0, 1, F.col(2), -1.0);
  add_cross(0, 2, F.col(1), +1.0);
  add_cross(1, 2, F.col(0), -1.0);
  add_cross(1, 0, F.col(2), +1.0);
  add_cross(2, 0, F.col(1), -1.0);
  add_cross(2, 1, F.col(0), +1.0);
}

}  // namespace tailor::material_detail
