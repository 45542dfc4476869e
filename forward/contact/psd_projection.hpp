#pragma once
// Projection of a small symmetric matrix onto the positive semidefinite cone (negative
// eigenvalues clamped to zero), for the per-pair Hessians of Newton's projected mode
// (Li et al. 2020, section 5: per-stencil PSD projection).
#include <Eigen/Eigenvalues>

namespace tailor::contact {

template <int N>
void project_to_psd(Eigen::Matrix<double, N, N>& matrix) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(matrix);
  if (eig.eigenvalues().minCoeff() >= 0.0) return;
  const Eigen::Matrix<double, N, 1> clamped = eig.eigenvalues().cwiseMax(0.0);
  matrix = eig.eigenvectors() * clamped.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace tailor::contact
