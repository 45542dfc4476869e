#include "forward/fem/materials/isotropic_projection.hpp"

#include <Eigen/Cholesky>
#include <cmath>

#include "forward/core/symmetric_eigen.hpp"

namespace tailor::material_detail {

template <int Dim>
void subtract_negative_modes(const RotationVariantSvd<Dim>& svd, const IsotropicModes<Dim>& modes,
                             Eigen::Matrix<double, Dim * Dim, Dim * Dim>& T) {
  using M = Eigen::Matrix<double, Dim, Dim>;
  using VecN = Eigen::Matrix<double, Dim * Dim, 1>;
  const M& U = svd.U;
  const M& V = svd.V;
  const double inv_sqrt2 = 1.0 / std::sqrt(2.0);
  for (int p = 0; p < IsotropicModes<Dim>::kPairs; ++p) {
    if (!(modes.twist(p) < 0.0) && !(modes.flip(p) < 0.0)) continue;
    const int i = IsotropicModes<Dim>::first(p), j = IsotropicModes<Dim>::second(p);
    const M A = U.col(i) * V.col(j).transpose(), B = U.col(j) * V.col(i).transpose();
    if (modes.twist(p) < 0.0) {
      const M W = inv_sqrt2 * (A - B);
      const Eigen::Map<const VecN> w(W.data());
      T.noalias() -= modes.twist(p) * w * w.transpose();
    }
    if (modes.flip(p) < 0.0) {
      const M W = inv_sqrt2 * (A + B);
      const Eigen::Map<const VecN> w(W.data());
      T.noalias() -= modes.flip(p) * w * w.transpose();
    }
  }
  // Scaling block: nothing to do when it is positive definite (cheap Cholesky test).
  if (Eigen::LLT<M>(modes.scaling).info() == Eigen::Success) return;
  Eigen::Matrix<double, Dim, 1> lambda;
  M vectors;
  symmetric_eigen(modes.scaling, lambda, vectors);
  for (int m = 0; m < Dim; ++m) {
    const double ev = lambda(m);
    if (!(ev < 0.0)) continue;
    const Eigen::Matrix<double, Dim, 1> y = vectors.col(m);
    const M S = U * y.asDiagonal() * V.transpose();  // sum_i y_i u_i v_i^T
    const Eigen::Map<const VecN> e(S.data());
    T.noalias() -= ev * e * e.transpose();
  }
}

template void subtract_negative_modes<2>(const RotationVariantSvd<2>&, const IsotropicModes<2>&,
                                         Eigen::Matrix<double, 4, 4>&);
template void subtract_negative_modes<3>(const RotationVariantSvd<3>&, const IsotropicModes<3>&,
                                         Eigen::Matrix<double, 9, 9>&);

}  // namespace tailor::material_detail
