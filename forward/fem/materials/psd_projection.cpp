#include "forward/fem/materials/psd_projection.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

namespace tailor::material_detail {

template <int N>
bool cholesky_accepts(const Eigen::Matrix<double, N, N>& A) {
  using M = Eigen::Matrix<double, N, N>;
  const double scale = A.diagonal().cwiseAbs().maxCoeff();
  if (!(scale > 0.0)) return A.isZero(0.0);  // zero diagonal: PSD only if A = 0
  M shifted = A;
  shifted.diagonal().array() += kPsdShift * scale;
  return Eigen::LLT<M>(shifted).info() == Eigen::Success;
}

template <int N>
bool project_psd(Eigen::Matrix<double, N, N>& A) {
  using M = Eigen::Matrix<double, N, N>;
  if (cholesky_accepts<N>(A)) return false;
  const Eigen::SelfAdjointEigenSolver<M> eig(A);
  const Eigen::Matrix<double, N, 1> clamped = eig.eigenvalues().cwiseMax(0.0);
  A.noalias() = eig.eigenvectors() * clamped.asDiagonal() * eig.eigenvectors().transpose();
  return true;
}

template bool cholesky_accepts<4>(const Eigen::Matrix<double, 4, 4>&);
template bool cholesky_accepts<9>(const Eigen::Matrix<double, 9, 9>&);
template bool project_psd<4>(Eigen::Matrix<double, 4, 4>&);
template bool project_psd<9>(Eigen::Matrix<double, 9, 9>&);

}  // namespace tailor::material_detail
